(** * The main theorems of the ROSGen library *)

(** Every main result of the library, restated in one place with its
    hypotheses and its meaning in plain English, and proved by applying
    the library lemma of the same name (the module is named in each
    proof).  A reader who trusts Coq, the definitions these statements
    mention, and the environment model ([Environment]: what [ros_spinOnce],
    the message queues, [ros_subscribe], [ros_advertise], [ros_publish],
    [ros_ok], [ros_rate_sleep], [Controller_initialize] and
    [Controller_step] mean) can take these statements as what the project proves, without
    reading the proofs.

    [make -C coq check-assumptions] runs [Print Assumptions] on every
    [Theorem] of this file ([coq/checks/assumptions.sh]) and fails, naming
    the theorem and its axioms, unless every one prints "Closed under the
    global context": no main result depends on an axiom (the classical
    axioms of Coq's real numbers, which Flocq loads, included).  [coqchk]
    re-checks this module with the others ([make -C coq check-proof]).

    The theorems are grouped as in DESIGN.md section 6: T1 (the generated
    functions meet their data delivery specifications), T2 (the whole
    node does, over whole runs), T3 (the paper's Section 6 properties of
    the generated code), T4 (the generator accepts exactly the well-formed
    models), T5 (the interpreter is sound); then the supporting results
    that the tests and the per-node files rely on.  The specifications
    ([callback_ddc], [input_glue_ddc], [output_glue_ddc], [node_ddc]) are
    in [DDC], where each is explained. *)

From Coq Require Import String List ZArith Bool.
From Flocq Require Import IEEE754.Binary IEEE754.Bits.
From ROSGen Require Import Errors Maps FloatBits.
From ROSGen Require Import Syntax Values Operators Memory Environment Semantics Typing Interp.
From ROSGen Require Import NodeModel ModelText Wellformed Generator Generatorspec Generatorproof Assignproof DDC.
From ROSGen Require FloatOps Loopproof Glueproof Interpproof.
From ROSGen Require Diagram Diagramgen Diagramproof Endtoend Link System.
Import ListNotations.

(** ** T1: every generated function meets its specification *)

(** Callbacks (the paper's Figure 10, for every model).  Hypotheses: the
    generator accepted model [m] and returned program [p]; [tp] is a
    subscribed topic of [m].  Meaning ([DDC.callback_ddc]): [p] has an
    internal function [c_callback] (where [c] is the topic's C name) such
    that, called with a pointer to a block (not a global) that holds a
    well-typed message [mv] of the topic's type, from any memory where the
    globals hold values of their types, every run terminates, emits no
    event, leaves the ROS world unchanged, and ends with the global
    [c_msg] holding a value of its type that has, at every leaf that the
    glue keeps there ([NodeModel.read_paths]: the paths of the topic's
    input relations that are not direct, and of a stamp copied from it),
    the leaf of [mv], and at every other leaf what it had before
    ([DDC.reads_copied]); with [Controller_U] holding a value of its type
    that has, at the leaf of every direct input relation of the topic
    (rule 4.16: an array element of a topic that is not timed), the
    relation's leaf of [mv], and elsewhere what it had before
    ([DDC.direct_copied]); with the topic's clock updated if it is timed
    and every other block unchanged; and such a run exists in every
    environment. *)
Theorem generate_callback_ddc:
  forall m p, generate m = OK p ->
  forall tp, In tp (subscribed m) -> callback_ddc m p tp.
Proof. exact Glueproof.generate_callback_ddc. Qed.

(** [input_glue] (the paper's Figure 12, for every model).  Hypothesis:
    [generate m = OK p].  Meaning ([DDC.input_glue_ddc]): [input_glue]
    terminates from any memory whose globals hold values of their types,
    emits nothing, changes only [Controller_U] (and the [c_new] flags of
    the timed topics), and leaves there a value of the inputs' struct
    type in which every input field named by an input relation that is
    not direct holds the scalar found at the relation's path in the
    global message of the relation's topic (or its fallback if the topic
    is stale), every derived input is exact, and the leaf of every
    direct relation (rule 4.16), which the callbacks wrote, keeps its
    value. *)
Theorem generate_input_glue_ddc:
  forall m p, generate m = OK p -> input_glue_ddc m p.
Proof. exact Glueproof.generate_input_glue_ddc. Qed.

(** The output glue of every published topic.  Hypotheses:
    [generate m = OK p]; [tp] is a published topic of [m].  Meaning
    ([DDC.output_glue_ddc]): [output_glue_c], called with a pointer to a
    block (not a global) that holds an object of the topic's message type,
    initialised or not, terminates, emits nothing, changes only that
    block, and leaves there the message [published_value] prescribes for
    the outputs [y] held by [Controller_Y] and the ROS time [now] of the
    world it runs in: every field named by an output relation of the
    topic holds the related field of [y], the stamp of a stamped topic
    holds [now]'s [sec] and [nsec] (on ROS 2, [builtin_interfaces_Time]:
    the seconds read as a signed 32-bit number, wrapped modulo 2^32 past
    2038, [DDC.stamp_sec], and [nanosec]), each constant string of the topic
    (rule 4.14) its bytes, every other scalar field is zero. *)
Theorem generate_output_glue_ddc:
  forall m p, generate m = OK p ->
  forall tp, In tp (published m) -> output_glue_ddc m p tp.
Proof. exact Glueproof.generate_output_glue_ddc. Qed.

(** ** Bounded sequences: what a callback receives *)

(** The environment delivers a message with its bounded sequences
    converted (issue 15, policy "truncate": [Environment.clamp]), and T2's
    [newest] is the converted message.  Meaning: for a bounded sequence
    at the model path [sp] of a well-typed arrival (a struct named
    [ros_seq_...] or [ros_string...] of [len], [truncated] and
    [data[n]], reached through no other bounded sequence:
    [DDC.bounded_at]), the message the callback receives has the length
    capped at [n], [truncated] 1 exactly when the sequence was longer
    than [n], and the first [min(len, n)] elements followed by zeros
    ([DDC.clamped_at]).  With T2's
    [input_values], this is what an input related to [sp.len],
    [sp.truncated] or [sp.data[j]] receives. *)
Theorem converted_sequence:
  forall m tp a sp id n t l,
  mval_has_type (composites m) (Tstruct (tp_msg tp)) (ar_msg a) ->
  bounded_at m tp sp id n t ->
  mval_get (ar_msg a) (path_steps (sp ++ [PField "len"%string])) = Some (MVscalar (Vint l)) ->
  clamped_at (converted m tp a) (ar_msg a) sp n t l.
Proof. exact DDC.converted_sequence. Qed.

(** ... and a bounded sequence of any element type (a sequence of
    messages, whose elements may hold sequences themselves): the length
    and [truncated] as above, each of the first [min(L, N)] elements
    converted in turn ([Environment.clamp]), then elements of zeros of the
    element type. *)
Theorem converted_sequence_elems:
  forall m tp a sp id n t l,
  mval_has_type (composites m) (Tstruct (tp_msg tp)) (ar_msg a) ->
  DDC.bounded_elems_at m tp sp id n t ->
  mval_get (ar_msg a) (path_steps (sp ++ [PField "len"%string])) = Some (MVscalar (Vint l)) ->
  let v := converted m tp a in
     mval_get v (path_steps (sp ++ [PField "len"%string])) = Some (MVscalar (Vint (Z.min l n)))
  /\ mval_get v (path_steps (sp ++ [PField "truncated"%string]))
     = Some (MVscalar (Vint (if (n <? l)%Z then 1 else 0)))
  /\ (forall j, (0 <= j < n)%Z ->
        mval_get v (path_steps (sp ++ [PField "data"%string; PIndex j]))
        = if (j <? Z.min l n)%Z
          then option_map (clamp (composites m) t) (mval_get (ar_msg a) (path_steps (sp ++ [PField "data"%string; PIndex j])))
          else Some (zero_mval (composites m) t)).
Proof. exact DDC.converted_sequence_elems. Qed.

(** What ROS carries of a published message ([DDC.sent], in T2's
    [publish_events]): a scalar field reached through no bounded sequence
    as the glue wrote it, ... *)
Theorem sent_scalar:
  forall m tp mv lp t x,
  mval_has_type (composites m) (Tstruct (tp_msg tp)) mv ->
  unbounded_path (composites m) (Tstruct (tp_msg tp)) (path_steps lp) = true ->
  type_at (composites m) (Tstruct (tp_msg tp)) (path_steps lp) = Some t ->
  mval_get mv (path_steps lp) = Some (MVscalar x) ->
  mval_get (sent m tp mv) (path_steps lp) = Some (MVscalar x).
Proof. exact DDC.sent_scalar. Qed.

(** ... and a bounded sequence at the model path [sp] with the length the
    glue wrote capped at its maximum [n] and exactly its first
    [min(len, n)] elements, zeros after (the wrapper sends these
    elements): with T2's [published_value], a published sequence carries
    the elements that the related outputs give, up to the length that the
    related length output gives, at most [n]. *)
Theorem sent_sequence:
  forall m tp mv sp id n t l,
  mval_has_type (composites m) (Tstruct (tp_msg tp)) mv ->
  bounded_at m tp sp id n t ->
  mval_get mv (path_steps (sp ++ [PField "len"%string])) = Some (MVscalar (Vint l)) ->
  clamped_at (sent m tp mv) mv sp n t l.
Proof. exact DDC.sent_sequence. Qed.

(** ** T2: data delivery correctness of every generated node *)

(** Hypothesis: [generate m = OK p].  Meaning ([DDC.node_ddc]): for every
    environment [ctx] (any schedule of message arrivals, any controller
    with any state type and step function) in which the messages arriving
    on subscribed topics are well typed and the controller's outputs are
    well typed, and for every number [n] of [true] answers of [ros_ok]:
    the program runs to completion ([program_behaves p ctx n t] for some
    trace [t]), and every such trace is the node's start followed by a
    run of [n] correct cycles ([DDC.run_ok]).  The start
    ([DDC.start_events]) is exactly: the controller is initialised
    ([Einit]; before it, the environment has no controller state and a
    step would be undefined), then every subscribed topic of the model,
    in model order, is subscribed to under its ROS name, with its message
    struct and its queue size ([Esubscribe]), then every published topic,
    in model order, is advertised likewise ([Eadvertise]).  In cycle [i],
    the controller is stepped once on inputs whose related fields are
    those of the newest message received on each relation's topic up to
    the [i]-th [ros_spinOnce] (zero if none), then each published topic,
    in model order, publishes the message whose related fields are the
    outputs of that step, its bounded sequences converted as the wrapper
    sends them ([DDC.sent]: [sent_scalar], [sent_sequence] above), then
    the cycle ends by sleeping with the
    model's period [nm_period_ms m] ([Esleep]).  Nothing else happens:
    the trace has no other event. *)
(** What T2's newest message is ([DDC.newest_arrival]): the newest
    message that the topic's callback received, that is, among the
    messages of each spin that the topic's queue keeps, the last one not
    dropped for a sequence of policy "reject" longer than its maximum
    ([DDC.received_on], [Environment.accepted]; the wrapper drops such a
    message before the glue's callback).  Without such messages, with a
    queue of at least 1, it is simply the newest arrival on the topic:
    that the queues keep the newest message is part of what T2 proves. *)
Theorem newest_arrival_raw:
  forall CS m (ctx : ros_context CS) tp i, (1 <= tp_queue tp)%nat ->
  (forall k a, In a (ctx_arrivals ctx k) -> ar_topic a = tp_name tp ->
     too_long (composites m) (Tstruct (tp_msg tp)) (ar_msg a) = false) ->
  newest_arrival m ctx tp i = last_on (tp_name tp) (arrivals_upto ctx i).
Proof. exact DDC.newest_arrival_raw. Qed.

Theorem generate_node_ddc:
  forall m p, generate m = OK p -> node_ddc m p.
Proof. exact Loopproof.generate_node_ddc. Qed.

(** T2 holds on both targets (rule 4.17): [node_ddc] quantifies over
    every context, whatever its [ctx_target] (ROS 1's [deliverable] or
    ROS 2's [rcl_deliverable], [Environment.spin_messages]); the per-node
    file restates it for the target it was generated for
    ([<node>_ddc_target : DDC.node_ddc_on target model the_program]). *)
Theorem generate_node_ddc_on:
  forall tg m p, generate m = OK p -> DDC.node_ddc_on tg m p.
Proof. intros tg m p G. apply DDC.node_ddc_on_target, Loopproof.generate_node_ddc, G. Qed.

(** ** T3: the paper's Section 6 properties *)

(** Relation consistency for [input_glue] (the paper's Figure 15): for any
    list of input relations [lir], the list [lg] of source expressions
    (fields of the topics' global messages) and the list [lc] of
    destination expressions (fields of [Controller_U]) that the generator
    builds from [lir] are related element by element to the relations of
    [lir], in order ([relation_consistency_input]). *)
Theorem relation_consistency_input_glue:
  forall m lir lg lc,
  lg = gen_list_global_expr_input_glue m lir ->
  lc = gen_list_controller_expr_input_glue m lir ->
  relation_consistency_input m lir lg lc.
Proof. exact Generatorproof.relation_consistency_input_glue. Qed.

(** Relation consistency for the output glue of the topic with C name [c]
    (the paper's Figure 15): the output relations [lor] of the topic, the
    source expressions [ls] (fields of [Controller_Y]) and the destination
    expressions [ld] (fields of [*command], a message of type [M]) that
    the generator builds are related element by element, in order. *)
Theorem relation_consistency_output_glue:
  forall m c M lor ls ld,
  lor = topic_outrels (make_tables m) c ->
  ls = gen_list_controller_expr_output_glue m lor ->
  ld = gen_list_message_expr_output_glue m M lor ->
  relation_consistency_output m c lor ls ld.
Proof. exact Generatorproof.relation_consistency_output_glue. Qed.

(** Valid assignment via type checking (the paper's Figure 16): when the
    check [type_checking_input_glue] accepts two lists of types, they are
    equal, i.e. the source and the destination of every copy have the same
    type. *)
Theorem type_checking_input_glue_sound:
  forall l1 l2, type_checking_input_glue l1 l2 = true -> l1 = l2.
Proof. exact Assignproof.type_checking_input_glue_sound. Qed.

(** For every well-formed model, the check of Figure 16 succeeds on the
    sources and destinations of the copies of [input_glue]. *)
Theorem type_checking_input_glue_generated:
  forall m, wf m = true ->
  type_checking_input_glue (map typeof (gen_list_global_expr_input_glue m (nm_inrels m)))
                           (map typeof (gen_list_controller_expr_input_glue m (nm_inrels m))) = true.
Proof. exact Assignproof.type_checking_input_glue_generated. Qed.

(** For every well-formed model and every topic, the same check succeeds
    on the sources and destinations of the copies of its output glue. *)
Theorem type_checking_output_glue_generated:
  forall m tp, wf m = true -> In tp (nm_topics m) ->
  type_checking_output_glue
    (map typeof (gen_list_controller_expr_output_glue m (topic_outrels (make_tables m) (tp_cname tp))))
    (map typeof (gen_list_message_expr_output_glue m (tp_msg tp) (topic_outrels (make_tables m) (tp_cname tp))))
  = true.
Proof. exact Assignproof.type_checking_output_glue_generated. Qed.

(** Hypotheses: [generate m = OK p]; [f] is any internal function of [p].
    Meaning: every assignment in the body of [f] is valid
    ([valid_assignments]): a scalar assigned to a place of the same
    scalar type, through a temporary of that type. *)
Theorem generate_valid_assignments:
  forall m p id f, generate m = OK p -> find_def p id = Some (Gfun (Internal f)) ->
  valid_assignments (prog_types p) (fn_temps f) (fn_body f).
Proof. exact Assignproof.generate_valid_assignments. Qed.

(** Preservation, first part: in the body of [loop], the call of the
    controller's step function comes right after the call of
    [input_glue], so nothing can change the inputs in between.
    Hypothesis: [generate m = OK p]. *)
Theorem loop_input_glue_then_step:
  forall m p, generate m = OK p ->
  exists f rest,
     find_def p loop_name = Some (Gfun (Internal f))
  /\ fn_body f = Sloop (seq_of ([Scall (Some ok_temp) (Evar ros_ok_name (Tfunction [] tint)) [];
                                 Sifthenelse (Etempvar ok_temp tint) Sskip Sbreak;
                                 call0 ros_spinOnce_name]
                                ++ call0 input_glue_name :: call0 (step_name m) :: rest)).
Proof. exact Assignproof.loop_input_glue_then_step. Qed.

(** Preservation: no generated function other than [input_glue] assigns
    (a part of) [Controller_U], except the callback of a topic that is not
    timed, which assigns exactly the leaves of its direct input relations
    (rule 4.16).  Hypotheses: [generate m = OK p]; [f] is the internal
    function [id] of [p], [id] is not [input_glue]; [pl] is a place that
    the body of [f] assigns. *)
Theorem generate_inputs_written_only_by_input_glue:
  forall m p id f, generate m = OK p -> find_def p id = Some (Gfun (Internal f)) ->
  id <> input_glue_name ->
  forall pl, In pl (assigned_places (fn_body f)) ->
     (exists r path, pl = Some (r, path) /\ r <> Rvar (nm_in_var m))
  \/ (exists tp ir, In tp (subscribed m) /\ is_timed m (tp_cname tp) = false
                    /\ id = callback_name (tp_cname tp) /\ In ir (direct_of m (tp_cname tp))
                    /\ pl = Some (Rvar (nm_in_var m), PField (ir_input ir) :: ir_elem ir)).
Proof. exact Assignproof.generate_inputs_written_only_by_input_glue. Qed.

(** Preservation: no generated function assigns (a part of)
    [Controller_Y]; only the controller writes its outputs. *)
Theorem generate_outputs_not_written:
  forall m p id f, generate m = OK p -> find_def p id = Some (Gfun (Internal f)) ->
  forall pl, In pl (assigned_places (fn_body f)) ->
  exists r path, pl = Some (r, path) /\ r <> Rvar (nm_out_var m).
Proof. exact Assignproof.generate_outputs_not_written. Qed.

(** Preservation: no generated function takes the address of
    [Controller_U] or [Controller_Y], so no write through a pointer can
    reach them. *)
Theorem generate_inputs_address_not_taken:
  forall m p id f, generate m = OK p -> find_def p id = Some (Gfun (Internal f)) ->
  stmt_takes_addr (nm_in_var m) (fn_body f) = false
  /\ stmt_takes_addr (nm_out_var m) (fn_body f) = false.
Proof. exact Assignproof.generate_inputs_address_not_taken. Qed.

(** ** T4: the generator accepts exactly the well-formed models *)

(** Completeness: every model that satisfies the rules of DESIGN.md
    section 4 ([Wellformed.wf]) is accepted by the generator. *)
Theorem generate_complete: forall m, wf m = true -> exists p, generate m = OK p.
Proof. exact Generatorproof.generate_complete. Qed.

(** Soundness: every model the generator accepts satisfies the rules. *)
Theorem generate_sound: forall m p, generate m = OK p -> wf m = true.
Proof. exact Generatorproof.generate_sound. Qed.

(** A model that breaks a rule is refused, with an error message. *)
Theorem generate_refuses: forall m, wf m = false -> exists msg, generate m = Error msg.
Proof. exact Generatorproof.generate_refuses. Qed.

(** The checker that names the culprit ([wf_check], which [generate] and
    the per-node files run) accepts exactly the models that satisfy the
    boolean rules [wf]. *)
Theorem wf_check_wf: forall m, wf_check m = OK tt <-> wf m = true.
Proof. exact Generatorproof.wf_check_wf. Qed.

(** ** T5: the interpreter is sound *)

(** For every environment [ctx], global environment [ge] and amount of
    fuel: whatever the interpreter's functions return for a statement
    ([exec_stmt_fuel]), a function call ([call_fuel]) or the deliveries
    of a [ros_spinOnce] ([deliver_fuel]) is a result of the corresponding
    big-step judgement of [Semantics]. *)
Theorem interp_sound:
  forall (CS : Type) (ctx : ros_context CS) (ge : genv) fuel,
  (forall e le m w s t le' m' w' out,
     exec_stmt_fuel ctx ge fuel e le m w s = Some (t, le', m', w', out) ->
     exec_stmt ctx ge e le m w s t le' m' w' out)
  /\ (forall m w fd vargs t m' w' v,
     call_fuel ctx ge fuel m w fd vargs = Some (t, m', w', v) ->
     eval_funcall ctx ge m w fd vargs t m' w' v)
  /\ (forall m w msgs t m' w',
     deliver_fuel ctx ge fuel m w msgs = Some (t, m', w') ->
     deliver ctx ge m w msgs t m' w').
Proof. intros CS ctx ge; exact (Interpproof.interp_sound ctx ge). Qed.

(** A whole run computed by the interpreter ([run_program], what the
    differential tests extract and compare with the compiled C) is a
    behaviour of the program: [main] terminates with that trace when
    [ros_ok] answers true [n] times. *)
Theorem run_program_sound:
  forall (CS : Type) (ctx : ros_context CS) fuel p n t v m' w',
  run_program fuel p ctx n = Some (t, v, m', w') ->
  program_behaves p ctx n t.
Proof. exact Interpproof.run_program_sound. Qed.

(** The same for the trace alone ([run_trace]). *)
Theorem run_trace_sound:
  forall (CS : Type) (ctx : ros_context CS) fuel p n t,
  run_trace fuel p ctx n = Some t -> program_behaves p ctx n t.
Proof. exact Interpproof.run_trace_sound. Qed.

(** With determinism: the trace the interpreter computes is the only
    behaviour of the program in that environment. *)
Theorem run_trace_exact:
  forall (CS : Type) (ctx : ros_context CS) fuel p n t t',
  run_trace fuel p ctx n = Some t -> program_behaves p ctx n t' -> t' = t.
Proof. exact Interpproof.run_trace_exact. Qed.

(** ** The controller: block diagrams (DESIGN.md rule 4.11) *)

(** A well-formed block diagram [d] ([Diagram.dg_wf]) means a stream
    function: [Diagram.dg_init] is its initial state, [Diagram.dg_step d s
    u] its next state and outputs from state [s] and inputs [u], with
    IEEE 754 arithmetic and two's complement wrap-around.  The generated
    [Controller_step] ([Diagramgen.step_function d]) computes exactly that:
    called in any global environment where the inputs global
    ([Controller_U]) holds inputs [u] whose fields have their types, the
    outputs global ([Controller_Y]) holds a struct of its fields, and the
    state global ([Controller_DW], when the diagram has states) holds the
    state [s], a struct of one value of its type per state, it
    terminates, emits no event, leaves the world as it was, and ends with
    the outputs global holding the outputs and the state global the next
    state that [dg_step] gives, every other block unchanged.  Since the
    semantics is deterministic ([semantics_determ]), this is the only
    run. *)
Theorem controller_step_correct:
  forall (CS : Type) (ctx : ros_context CS) (ge : genv) (d : Diagram.diagram) (m : mem) (w : world CS)
         (s u : mval) (bu bs by_ : Values.block) (tyU tyY tyS : type)
         (fsY sfs : list (ident * mval)),
  Diagram.dg_wf d = true ->
  find_var ge (Diagram.dg_in_var d) = Some (bu, Tstruct (Diagram.dg_in_struct d)) ->
  get_block m bu = Some (tyU, u) ->
  (forall f q, find_assoc f (Diagram.dg_inputs d) = Some q ->
     exists v, mval_get u [Sfield f] = Some (MVscalar v) /\ val_has_type v (ctype_of_prim q)) ->
  find_var ge (Diagram.dg_out_var d) = Some (by_, Tstruct (Diagram.dg_out_struct d)) ->
  get_block m by_ = Some (tyY, MVstruct fsY) -> map fst fsY = map fst (Diagram.dg_outputs d) ->
  (Diagramgen.has_states d = true ->
     find_var ge (Diagram.dg_state_var d) = Some (bs, Tstruct (Diagram.dg_state_struct d))
     /\ get_block m bs = Some (tyS, s) /\ by_ <> bs) ->
  s = MVstruct sfs -> map fst sfs = map Diagram.st_name (Diagram.dg_states d) ->
  (forall st, In st (Diagram.dg_states d) ->
     exists v, mval_get s [Sfield (Diagram.st_name st)] = Some (MVscalar v)
               /\ val_has_type v (ctype_of_prim (Diagram.st_type st))) ->
  exists m',
     eval_funcall ctx ge m w (Internal (Diagramgen.step_function d)) [] [] m' w Vundef
  /\ get_block m' by_ = Some (tyY, snd (Diagram.dg_step d s u))
  /\ (Diagramgen.has_states d = true -> get_block m' bs = Some (tyS, fst (Diagram.dg_step d s u)))
  /\ (forall b', b' <> by_ -> (Diagramgen.has_states d = true -> b' <> bs) -> get_block m' b' = get_block m b')
  /\ mem_next m' = mem_next m.
Proof.
  intros CS ctx ge d m w s u bu bs by_ tyU tyY tyS fsY sfs WF HU GU Uty HY GY NY HS SF NS Sty.
  eapply (Diagramproof.step_call ctx ge d m w s u bu bs HU (ex_intro _ tyU GU) Uty); eauto.
  - intros H; destruct (HS H) as [A [B _]]; eauto.
  - intros H; destruct (HS H) as [_ [B _]]; eauto.
  - intros H; destruct (HS H) as [_ [_ C]]; eauto.
Qed.

(** The rules of a diagram as the per-node files compute them
    ([Diagram.dg_check]: the signals' types in a trie, duplicates found
    by [find_dup]) imply [dg_wf]: a node file proves [dg_wf the_diagram]
    from [dg_check the_diagram = true], computed in time about linear in
    the number of blocks (BENCHMARKS.md section 6). *)
Theorem dg_check_wf: forall d, Diagram.dg_check d = true -> Diagram.dg_wf d = true.
Proof. exact Diagram.dg_check_wf. Qed.

(** [Controller_initialize] ([Diagramgen.init_function d]) stores the
    diagram's initial state [Diagram.dg_init d] into the state global, and
    changes no other block. *)
Theorem controller_init_correct:
  forall (CS : Type) (ctx : ros_context CS) (ge : genv) (d : Diagram.diagram) (m : mem) (w : world CS)
         (bs : Values.block) (tyS : type) (sfs0 : list (ident * mval)),
  Diagram.dg_wf d = true -> Diagramgen.has_states d = true ->
  find_var ge (Diagram.dg_state_var d) = Some (bs, Tstruct (Diagram.dg_state_struct d)) ->
  get_block m bs = Some (tyS, MVstruct sfs0) -> map fst sfs0 = map Diagram.st_name (Diagram.dg_states d) ->
  exists m',
     eval_funcall ctx ge m w (Internal (Diagramgen.init_function d)) [] [] m' w Vundef
  /\ get_block m' bs = Some (tyS, Diagram.dg_init d)
  /\ (forall b', b' <> bs -> get_block m' b' = get_block m b')
  /\ mem_next m' = mem_next m.
Proof.
  intros CS ctx ge d m w bs tyS sfs0 WF H HSv G N.
  apply (Diagramproof.init_call ctx ge d m w (MVstruct sfs0) bs) with (tyS := tyS) (sfs0 := sfs0); auto.
  intros _. split; eauto.
Qed.

(** The whole node, its controller a diagram: T2 in the environments
    whose controller is the diagram [d] ([Endtoend.diagram_ctx]).  For
    every node model [m] and diagram [d] accepted by [generate] and
    [dg_wf], [d] having [m]'s controller interface, every schedule of
    well-typed messages, either target [tg] and every number [n] of
    cycles: the node terminates, and its trace is its start followed by [n] cycles in each
    of which the diagram steps once, from the state its previous step left
    ([dg_init] at first), on the related fields of the newest messages
    ([DDC.input_values]), and the node publishes the related fields of the
    diagram's outputs ([DDC.published_value]).  With
    [controller_step_correct] (the generated C computes [dg_step], and
    touches nothing but the outputs and its state), this is the node's
    end-to-end property; how the two meet is in [Endtoend]'s header. *)
Theorem diagram_node_ddc:
  forall m p (d : Diagram.diagram), generate m = OK p -> Diagram.dg_wf d = true ->
  Endtoend.dg_matches m d = true ->
  forall arrivals clock tg n, arrivals_wt m (Endtoend.diagram_ctx m d arrivals clock tg) ->
     (exists t, program_behaves p (Endtoend.diagram_ctx m d arrivals clock tg) n t)
  /\ (forall t, program_behaves p (Endtoend.diagram_ctx m d arrivals clock tg) n t ->
      exists (s : nat -> mval) (evs : nat -> trace),
         s O = Diagram.dg_init d
      /\ t = start_events m ++ concat (map evs (seq 0 n))
      /\ forall i, (i < n)%nat ->
           exists u y mvs,
              evs i = Estep u y :: publish_events m (published m) mvs ++ [Esleep (nm_period_ms m)]
           /\ input_values m (Endtoend.diagram_ctx m d arrivals clock tg) i u
           /\ Diagram.dg_step d (s i) u = (s (S i), y)
           /\ Forall2 (published_value m y (clock (S i)) (newest_by m (Endtoend.diagram_ctx m d arrivals clock tg) i)) (published m) mvs).
Proof. exact Endtoend.diagram_node_ddc. Qed.

(** The whole node as one program, its controller linked in (T8): [Link.link p d] is the
    glue [p] with the generated [Controller_initialize] and
    [Controller_step] ([Diagramgen.init_function], [step_function]) in place of
    their declarations, and the state global [Controller_DW] (if the
    diagram has states) in memory.  For every node model [m] and diagram
    [d] accepted by [generate] and [dg_wf], [d] having [m]'s controller
    interface and state names that clash with none of the glue's
    ([Link.link_fresh]), in every environment (with any controller: the
    linked program calls none), for every schedule of well-typed messages
    and every number [n] of cycles, the linked program terminates; its
    trace is the registrations of the topics followed by [n] cycles in
    each of which the node publishes the related fields of the diagram's
    outputs, the diagram stepped once on the related fields of the newest
    messages from the state its previous step left ([dg_init] first).
    The proof is a simulation ([Link.sim]) of the glue's run in the
    environment whose controller is the diagram ([diagram_node_ddc])
    by the linked program's run, the state moving from the environment
    into [Controller_DW], with [controller_step_correct] for each call. *)
Theorem linked_node_ddc:
  forall m p (d : Diagram.diagram), generate m = OK p -> Diagram.dg_wf d = true ->
  Endtoend.dg_matches m d = true -> Link.link_fresh m d = true ->
  forall arrivals clock tg n (CSL : Type) (ctxL : ros_context CSL),
  ctx_arrivals ctxL = arrivals -> ctx_time ctxL = clock -> ctx_target ctxL = tg ->
  arrivals_wt m (Endtoend.diagram_ctx m d arrivals clock tg) ->
     (exists t, program_behaves (Link.link p d) ctxL n t)
  /\ (forall t, program_behaves (Link.link p d) ctxL n t ->
      exists (s : nat -> mval) (evs : nat -> trace),
         s O = Diagram.dg_init d
      /\ t = Link.linked_start_events m ++ concat (map evs (seq 0 n))
      /\ forall i, (i < n)%nat ->
           exists u y mvs,
              evs i = publish_events m (published m) mvs ++ [Esleep (nm_period_ms m)]
           /\ input_values m (Endtoend.diagram_ctx m d arrivals clock tg) i u
           /\ Diagram.dg_step d (s i) u = (s (S i), y)
           /\ Forall2 (published_value m y (clock (S i)) (newest_by m (Endtoend.diagram_ctx m d arrivals clock tg) i)) (published m) mvs).
Proof. exact Link.linked_node_ddc. Qed.

(** ** The semantics *)

(** The big-step semantics is deterministic: in a given environment, a
    statement, a function call or a delivery of messages started in the
    same state has at most one result (trace, final state, outcome). *)
Theorem semantics_determ:
  forall (CS : Type) (ctx : ros_context CS) (ge : genv),
  (forall e le m w s t1 le1 m1 w1 out1, exec_stmt ctx ge e le m w s t1 le1 m1 w1 out1 ->
     forall t2 le2 m2 w2 out2, exec_stmt ctx ge e le m w s t2 le2 m2 w2 out2 ->
     t1 = t2 /\ le1 = le2 /\ m1 = m2 /\ w1 = w2 /\ out1 = out2)
  /\ (forall m w fd vargs t1 m1 w1 v1, eval_funcall ctx ge m w fd vargs t1 m1 w1 v1 ->
     forall t2 m2 w2 v2, eval_funcall ctx ge m w fd vargs t2 m2 w2 v2 ->
     t1 = t2 /\ m1 = m2 /\ w1 = w2 /\ v1 = v2)
  /\ (forall m w msgs t1 m1 w1, deliver ctx ge m w msgs t1 m1 w1 ->
     forall t2 m2 w2, deliver ctx ge m w msgs t2 m2 w2 ->
     t1 = t2 /\ m1 = m2 /\ w1 = w2).
Proof. intros CS ctx ge; exact (Semantics.semantics_determ ctx ge). Qed.

(** A program has at most one behaviour in a given environment: the run
    that T2 describes is the run of the node. *)
Theorem program_behaves_determ:
  forall (CS : Type) p (ctx : ros_context CS) n t1 t2,
  program_behaves p ctx n t1 -> program_behaves p ctx n t2 -> t1 = t2.
Proof. exact Semantics.program_behaves_determ. Qed.

(** The executable type checker is sound: a program it accepts is well
    typed ([Typing.wt_program]). *)
Theorem check_program_correct: forall p, check_program p = true -> wt_program p.
Proof. exact Typing.check_program_correct. Qed.

(** The arithmetic operators ([Operators]) compute values of the type
    the typing rules announce: the result of [e1 op e2] on operands of
    type [ty] has type [binop_type op ty] (e.g. [int] for a comparison),
    and likewise for [op e].  Undefined behaviour (signed overflow,
    division by zero, [INT_MIN / -1]) has no result at all. *)
Theorem sem_binop_type:
  forall op ty v1 v2 v ty',
  sem_binop op ty v1 v2 = Some v -> binop_type op ty = Some ty' -> val_has_type v ty'.
Proof. exact Operators.sem_binop_type. Qed.

Theorem sem_unop_type:
  forall op ty v r ty',
  sem_unop op ty v = Some r -> unop_type op ty = Some ty' -> val_has_type r ty'.
Proof. exact Operators.sem_unop_type. Qed.

(** The queue model of the environment keeps the newest message: for a
    subscription [s] with a queue of size at least 1, the last message
    that one [ros_spinOnce] delivers to [s] ([Environment.deliverable])
    is the last message that arrived on its topic. *)
Theorem last_delivered_deliverable:
  forall subs s msgs, In s subs -> (1 <= sub_queue s)%nat ->
  Loopfacts.last_delivered s (deliverable subs msgs) = last_on (sub_topic s) msgs.
Proof. exact Loopfacts.last_delivered_deliverable. Qed.

(** The same on ROS 2 ([Environment.rcl_deliverable]: each subscription's
    KEEP_LAST history of depth [sub_queue s], one subscription after
    the other): for distinct subscriptions, the last message that one spin
    delivers to [s] is the last arrival on its topic. *)
Theorem last_delivered_rcl_deliverable:
  forall subs s msgs, NoDup subs -> In s subs -> (1 <= sub_queue s)%nat ->
  Loopfacts.last_delivered s (rcl_deliverable subs msgs) = last_on (sub_topic s) msgs.
Proof. exact Loopfacts.last_delivered_rcl_deliverable. Qed.

(** ** The shape of the generated program (used by T1 and T2) *)

(** Hypothesis everywhere: [generate m = OK p]. *)

(** All global names of [p] are distinct. *)
Theorem generate_names_distinct:
  forall m p, generate m = OK p -> NoDup (map fst (prog_defs p)).
Proof. exact Generatorproof.generate_names_distinct. Qed.

(** No parameter, temporary or local variable of a generated function has
    the name of a global. *)
Theorem generate_locals_fresh:
  forall m p x, generate m = OK p -> In x (local_names m) -> ~ In x (map fst (prog_defs p)).
Proof. exact Generatorproof.generate_locals_fresh. Qed.

(** For each subscribed topic [tp] (C name [c], message type [M]): [p]
    has the global [c_msg] of type [struct M] and the function
    [c_callback], whose body copies into [c_msg] the leaves of [*msg]
    that the glue keeps there ([read_leaves]: those named by
    [read_paths]), in the order of [leaves], through temporaries of the
    leaves' types, and then, if the topic is timed (rule 4.12), updates
    its clock ([clock_stmts]: [c_time = ros_now(); c_new = 1; c_rcvd =
    1;]), else copies the leaves of its direct input relations (rule
    4.16: [direct_of]) into [Controller_U], in model order. *)
Theorem generate_callback:
  forall m p tp, generate m = OK p -> In tp (subscribed m) ->
  let c := tp_cname tp in
  let M := tp_msg tp in
  find_def p (msg_var c) = Some (Gvar (Tstruct M))
  /\ exists f,
     find_def p (callback_name c) = Some (Gfun (Internal f))
  /\ fn_return f = Tvoid
  /\ fn_params f = [(msg_param, tptr (Tstruct M))]
  /\ fn_vars f = []
  /\ fn_body f = (let base := seq_of (map (leaf_copy (prog_types p) (Evar (msg_var c) (Tstruct M))
                                                                (deref_param msg_param M))
                                        (read_leaves m tp)) in
                  if is_timed m c then Ssequence base (clock_stmts c)
                  else match direct_of m c with
                       | [] => base
                       | ds => Ssequence base (seq_of (map (direct_copy m (make_tables m) M) ds))
                       end)
  /\ NoDup (map fst (fn_temps f))
  /\ (forall l, In l (read_leaves m tp) ->
        find_assoc (temp_name (snd l)) (fn_temps f) = Some (ctype_of_prim (snd l)))
  /\ (is_timed m c = false -> forall ir, In ir (direct_of m c) ->
        find_assoc (temp_name (inrel_prim (make_tables m) ir)) (fn_temps f)
        = Some (ctype_of_prim (inrel_prim (make_tables m) ir)))
  /\ (is_timed m c = true -> find_assoc (temp_name Puint64) (fn_temps f) = Some (Tlong Unsigned)).
Proof. exact Generatorproof.generate_callback. Qed.

(** [input_glue] is the sequence of the copies of the input relations
    that are not direct (rule 4.16: [glue_inrels]), in model order
    ([input_base]), then, if some topic is timed (rule
    4.12), [timed_stmts]: [_now = ros_now();] (only if a fallback or an
    [age_ms] reads an age: [reads_age]), the fallbacks, the derived
    inputs, and the [c_new] flags cleared.  The temporaries [_now] and
    [_age] are declared only if an age is read, [_t_uchar] only if a
    flag is copied ([reads_flag]) or an input is a [bool]. *)
Theorem generate_input_glue:
  forall m p, generate m = OK p ->
  exists f,
     find_def p input_glue_name = Some (Gfun (Internal f))
  /\ fn_return f = Tvoid /\ fn_params f = [] /\ fn_vars f = []
  /\ fn_body f = match timed m with
                 | [] => input_base m
                 | _ :: _ => Ssequence (input_base m) (timed_stmts m (make_tables m))
                 end
  /\ NoDup (map fst (fn_temps f))
  /\ (forall ir, In ir (glue_inrels m) ->
        find_assoc (temp_name (inrel_prim (make_tables m) ir)) (fn_temps f)
        = Some (ctype_of_prim (inrel_prim (make_tables m) ir)))
  /\ (timed m <> [] ->
        (reads_age m = true ->
           find_assoc now_temp (fn_temps f) = Some (Tlong Unsigned)
        /\ find_assoc age_temp (fn_temps f) = Some (Tlong Unsigned))
     /\ (reads_flag m = true -> find_assoc (temp_name Pbool) (fn_temps f) = Some (ctype_of_prim Pbool))).
Proof. exact Generatorproof.generate_input_glue. Qed.

(** A node with a timed topic declares [ros_now], and each timed topic
    has its clock: [unsigned long long c_time; unsigned char c_new,
    c_rcvd;] (rule 4.12). *)
Theorem generate_now_external:
  forall m p, generate m = OK p -> timed m <> [] ->
  find_def p ros_now_name = Some (Gfun (External EF_ros_now [] (Tlong Unsigned))).
Proof. exact Generatorproof.generate_now_external. Qed.

Theorem generate_clock_globals:
  forall m p tp, generate m = OK p -> In tp (timed m) ->
     find_def p (time_var (tp_cname tp)) = Some (Gvar (Tlong Unsigned))
  /\ find_def p (new_var (tp_cname tp)) = Some (Gvar (Tint I8 Unsigned))
  /\ find_def p (rcvd_var (tp_cname tp)) = Some (Gvar (Tint I8 Unsigned)).
Proof. exact Generatorproof.generate_clock_globals. Qed.

(** For each published topic [tp], [output_glue_c] zeroes every leaf of
    [*command], then performs the copies of the topic's output relations,
    in model order ([output_base]), then, if the topic is stamped (rule
    4.13), writes the time's [sec] and [nsec] into the stamp
    ([stamp_stmts]; on ROS 2 [(int)] of the seconds, and [nanosec]), and last stores the topic's constant strings (rule
    4.14: [strings_stmts], the length then each byte). *)
Theorem generate_output_glue:
  forall m p tp, generate m = OK p -> In tp (published m) ->
  let c := tp_cname tp in
  let M := tp_msg tp in
  let lor := topic_outrels (make_tables m) c in
  exists f,
     find_def p (output_glue_name c) = Some (Gfun (Internal f))
  /\ fn_return f = Tvoid
  /\ fn_params f = [(command_param, tptr (Tstruct M))]
  /\ fn_vars f = []
  /\ fn_body f
     = Ssequence (match topic_stamp m c with
                  | None => output_base m tp
                  | Some sp => Ssequence (output_base m tp) (stamp_stmts m (make_tables m) c M sp)
                  end)
                 (strings_stmts m c M)
  /\ NoDup (map fst (fn_temps f))
  /\ (forall o, In o lor ->
        find_assoc (temp_name (outrel_prim (make_tables m) o)) (fn_temps f)
        = Some (ctype_of_prim (outrel_prim (make_tables m) o)))
  /\ (forall sp, topic_stamp m c = Some sp ->
        find_assoc (temp_name Puint32) (fn_temps f) = Some (ctype_of_prim Puint32)).
Proof. exact Generatorproof.generate_output_glue. Qed.

(** [loop]: one local message [c_cmd] per published topic, and a cycle
    [_ok = ros_ok(); if (_ok) ; else break; ros_spinOnce(); input_glue();
    Controller_step();], then for each published topic
    [output_glue_c(&c_cmd); ros_publish_c(&c_cmd);], then
    [ros_rate_sleep();]. *)
Theorem generate_loop:
  forall m p, generate m = OK p ->
  exists f,
     find_def p loop_name = Some (Gfun (Internal f))
  /\ fn_return f = Tvoid /\ fn_params f = []
  /\ fn_vars f = map (fun tp => (cmd_var (tp_cname tp), Tstruct (tp_msg tp))) (published m)
  /\ NoDup (map fst (fn_vars f))
  /\ fn_temps f = [(ok_temp, tint)]
  /\ fn_body f
     = Sloop (Ssequence (Scall (Some ok_temp) (Evar ros_ok_name (Tfunction [] tint)) [])
             (Ssequence (Sifthenelse (Etempvar ok_temp tint) Sskip Sbreak)
             (Ssequence (call0 ros_spinOnce_name)
             (Ssequence (call0 input_glue_name)
             (Ssequence (call0 (step_name m))
                        (seq_of (flat_map publish_stmts (published m)
                                 ++ [call0 ros_rate_sleep_name]))))))).
Proof. exact Generatorproof.generate_loop. Qed.

(** [main] initialises ROS and the controller, subscribes every
    subscribed topic with its callback, advertises every published topic,
    runs [loop] and returns 0. *)
Theorem generate_main:
  forall m p, generate m = OK p ->
  prog_main p = main_name
  /\ exists f,
     find_def p main_name = Some (Gfun (Internal f))
  /\ fn_return f = tint /\ fn_params f = [] /\ fn_vars f = [] /\ fn_temps f = []
  /\ fn_body f = seq_of ([call0 ros_init_name; call0 (init_name m)]
                         ++ map subscribe_stmt (subscribed m)
                         ++ map advertise_stmt (published m)
                         ++ [call0 loop_name; Sreturn (Some (Econst_int 0 tint))]).
Proof. exact Generatorproof.generate_main. Qed.

(** The ROS API functions that do not depend on the topics
    ([ros_rate_sleep] carries the model's period), the controller's two
    functions and its two global structs, under their names, with their
    meanings ([external_function] tags). *)
Theorem generate_externals:
  forall m p, generate m = OK p ->
     find_def p ros_init_name = Some (Gfun (External EF_ros_init [] Tvoid))
  /\ find_def p ros_ok_name = Some (Gfun (External EF_ros_ok [] tint))
  /\ find_def p ros_spinOnce_name = Some (Gfun (External EF_ros_spinOnce [] Tvoid))
  /\ find_def p ros_rate_sleep_name = Some (Gfun (External (EF_ros_rate_sleep (nm_period_ms m)) [] Tvoid))
  /\ find_def p (init_name m)
     = Some (Gfun (External (EF_controller_initialize (nm_in_var m) (nm_out_var m)) [] Tvoid))
  /\ find_def p (step_name m)
     = Some (Gfun (External (EF_controller_step (nm_in_var m) (nm_out_var m)) [] Tvoid))
  /\ find_def p (nm_in_var m) = Some (Gvar (Tstruct (nm_in_struct m)))
  /\ find_def p (nm_out_var m) = Some (Gvar (Tstruct (nm_out_struct m))).
Proof. exact Generatorproof.generate_externals. Qed.

(** The ROS API functions of each topic: [ros_subscribe_c] for a
    subscribed topic (its ROS name, message type and queue size), and
    [ros_advertise_c], [ros_publish_c] for a published one. *)
Theorem generate_topic_externals:
  forall m p tp, generate m = OK p -> In tp (nm_topics m) ->
  match tp_dir tp with
  | Subscribe =>
      find_def p (subscribe_name (tp_cname tp))
      = Some (Gfun (External (EF_ros_subscribe (tp_name tp) (tp_msg tp) (tp_queue tp))
                             [tptr (callback_type (tp_msg tp))] Tvoid))
  | Publish =>
      find_def p (advertise_name (tp_cname tp))
      = Some (Gfun (External (EF_ros_advertise (tp_name tp) (tp_msg tp) (tp_queue tp)) [] Tvoid))
   /\ find_def p (publish_name (tp_cname tp))
      = Some (Gfun (External (EF_ros_publish (tp_name tp) (tp_msg tp))
                             [tptr (Tstruct (tp_msg tp))] Tvoid))
  end.
Proof. exact Generatorproof.generate_topic_externals. Qed.

(** Which generated function assigns what: a callback assigns only its
    topic's global message and, if the topic is timed, its clock, else
    the leaves of [Controller_U] of its direct input relations (rule
    4.16); [input_glue] only fields of [Controller_U] (or their elements) and
    the [c_new] flags of the timed topics; [output_glue_c] only through
    its pointer parameter [command]; [loop] and [main] assign nothing. *)
Theorem generate_assigned_places:
  forall m p id f, generate m = OK p -> find_def p id = Some (Gfun (Internal f)) ->
  forall pl, In pl (assigned_places (fn_body f)) ->
     (exists tp path, In tp (subscribed m) /\ id = callback_name (tp_cname tp)
                      /\ pl = Some (Rvar (msg_var (tp_cname tp)), path))
  \/ (exists tp x, In tp (timed m) /\ id = callback_name (tp_cname tp)
                   /\ In x (clock_names tp) /\ pl = Some (Rvar x, []))
  \/ (exists tp ir, In tp (subscribed m) /\ id = callback_name (tp_cname tp) /\ In ir (direct_of m (tp_cname tp))
                    /\ pl = Some (Rvar (nm_in_var m), PField (ir_input ir) :: ir_elem ir))
  \/ (exists x path, id = input_glue_name /\ pl = Some (Rvar (nm_in_var m), PField x :: path))
  \/ (exists tp, In tp (timed m) /\ id = input_glue_name /\ pl = Some (Rvar (new_var (tp_cname tp)), []))
  \/ (exists tp path, In tp (published m) /\ id = output_glue_name (tp_cname tp)
                      /\ pl = Some (Rderef command_param, path)).
Proof. exact Assignproof.generate_assigned_places. Qed.

(** The only addresses the generated code takes are those of the loop's
    local messages [c_cmd] (in [loop]) and of the callbacks (in [main]). *)
Theorem generate_addresses_taken:
  forall m p id f x, generate m = OK p -> find_def p id = Some (Gfun (Internal f)) ->
  stmt_takes_addr x (fn_body f) = true ->
     (exists tp, In tp (published m) /\ id = loop_name /\ x = cmd_var (tp_cname tp))
  \/ (exists tp, In tp (subscribed m) /\ id = main_name /\ x = callback_name (tp_cname tp)).
Proof. exact Assignproof.generate_addresses_taken. Qed.

(** ** Messages *)

(** For a model that satisfies the rules ([wf_facts], which
    [Wellformed.wf] gives): the leaves of a message, which the callbacks
    copy and the output glue zeroes, are exactly its paths to a primitive
    (every field, every array element), with their primitive types. *)
Theorem leaves_spec:
  forall m id p q, wf_facts m ->
  In (p, q) (leaves (nm_msgs m) id) <-> resolve (nm_msgs m) (FTmsg id) p = Some (FTprim q).
Proof. exact Generatorspec.leaves_spec. Qed.

(** Each leaf appears once: a callback copies each leaf that the node
    reads exactly once. *)
Theorem leaves_nodup:
  forall m id, wf_facts m -> NoDup (map fst (leaves (nm_msgs m) id)).
Proof. exact Generatorspec.leaves_nodup. Qed.

(** ** The model text ([ModelText]) *)

(** The per-node file prints the model its theorems are about
    ([print_model]), and [pyrosgen generate] compares that text with its
    own reading of the YAML file.  The comparison is meaningful because
    the text determines the model's items: for two models whose lines
    contain no line feed ([lines_ok], which the names [Wellformed]
    accepts guarantee), the same text means the same lines, and in
    particular the same topic lines (ROS name, C name, direction, ROS
    type, queue size), the same input relation lines and the same output
    relation lines, in the same order. *)
Theorem print_model_items:
  forall m1 m2, lines_ok m1 = true -> lines_ok m2 = true -> print_model m1 = print_model m2 ->
     model_lines m1 = model_lines m2
  /\ map topic_line (nm_topics m1) = map topic_line (nm_topics m2)
  /\ map inrel_line (nm_inrels m1) = map inrel_line (nm_inrels m2)
  /\ map outrel_line (nm_outrels m1) = map outrel_line (nm_outrels m2).
Proof. exact ModelText.print_model_items. Qed.

(** ** Floats *)

(** Decoding a 64-bit pattern into a float ([float64_of_bits], written
    without axioms, unlike Flocq's [b64_of_bits]) and encoding it back
    ([bits_of_b64]) gives the pattern, for every pattern, NaN payloads
    included. *)
Theorem bits_of_float64_of_bits:
  forall z, (0 <= z < 2 ^ 64)%Z -> bits_of_b64 (float64_of_bits z) = z.
Proof. exact FloatBits.bits_of_float64_of_bits. Qed.

(** Encoding a [double] to its pattern and decoding it gives it back. *)
Theorem float64_of_bits_of_float64:
  forall f : float64, float64_of_bits (bits_of_b64 f) = f.
Proof. exact FloatBits.float64_of_bits_of_float64. Qed.

(** The same two facts for [float] (binary32). *)
Theorem bits_of_float32_of_bits:
  forall z, (0 <= z < 2 ^ 32)%Z -> bits_of_b32 (float32_of_bits z) = z.
Proof. exact FloatBits.bits_of_float32_of_bits. Qed.

Theorem float32_of_bits_of_float32:
  forall f : float32, float32_of_bits (bits_of_b32 f) = f.
Proof. exact FloatBits.float32_of_bits_of_float32. Qed.

(** ** Float arithmetic without axioms ([FloatOps]) *)

(** IEEE 754 multiplication and addition of [double]s and [float]s,
    rounded to nearest even, computed with Coq's [SpecFloat] rather than
    Flocq's real-number-based [Bmult]/[Bplus] (which would make any
    theorem that computes with them depend on the classical axioms of the
    reals), commute when at most one operand is a NaN. *)
Theorem mul64_comm:
  forall x y : float64, is_nan 53 1024 x = false \/ is_nan 53 1024 y = false ->
  FloatOps.mul64 x y = FloatOps.mul64 y x.
Proof. exact FloatOps.mul64_comm. Qed.

Theorem add64_comm:
  forall x y : float64, is_nan 53 1024 x = false \/ is_nan 53 1024 y = false ->
  FloatOps.add64 x y = FloatOps.add64 y x.
Proof. exact FloatOps.add64_comm. Qed.

Theorem mul32_comm:
  forall x y : float32, is_nan 24 128 x = false \/ is_nan 24 128 y = false ->
  FloatOps.mul32 x y = FloatOps.mul32 y x.
Proof. exact FloatOps.mul32_comm. Qed.

Theorem add32_comm:
  forall x y : float32, is_nan 24 128 x = false \/ is_nan 24 128 y = false ->
  FloatOps.add32 x y = FloatOps.add32 y x.
Proof. exact FloatOps.add32_comm. Qed.

(** Worked examples, on bit patterns (the results gcc computes):
    [0.1 * 3] and [0.1 + 0.2] are [0.30000000000000004]; [0.1f * 3.0f];
    a tie rounded to even (1.5 times the least subnormal); [1 / 3];
    overflow to infinity; [inf * 0] is the default NaN; a NaN operand is
    propagated, quieted. *)
Theorem mul64_example:
  FloatOps.on_bits64 FloatOps.mul64 0x3FB999999999999A 0x4008000000000000 = 0x3FD3333333333334%Z.
Proof. exact FloatOps.mul64_example. Qed.

Theorem add64_example:
  FloatOps.on_bits64 FloatOps.add64 0x3FB999999999999A 0x3FC999999999999A = 0x3FD3333333333334%Z.
Proof. exact FloatOps.add64_example. Qed.

Theorem mul32_example: FloatOps.on_bits32 FloatOps.mul32 0x3DCCCCCD 0x40400000 = 0x3E99999A%Z.
Proof. exact FloatOps.mul32_example. Qed.

Theorem mul64_tie_even: FloatOps.on_bits64 FloatOps.mul64 0x1 0x3FF8000000000000 = 0x2%Z.
Proof. exact FloatOps.mul64_tie_even. Qed.

Theorem div64_example:
  FloatOps.on_bits64 FloatOps.div64 0x3FF0000000000000 0x4008000000000000 = 0x3FD5555555555555%Z.
Proof. exact FloatOps.div64_example. Qed.

Theorem mul64_overflow:
  FloatOps.on_bits64 FloatOps.mul64 0x7FE1CCF385EBC8A0 0x4024000000000000 = 0x7FF0000000000000%Z.
Proof. exact FloatOps.mul64_overflow. Qed.

Theorem mul64_inf_zero:
  FloatOps.on_bits64 FloatOps.mul64 0x7FF0000000000000 0x0 = 0xFFF8000000000000%Z.
Proof. exact FloatOps.mul64_inf_zero. Qed.

Theorem mul64_nan_payload:
  FloatOps.on_bits64 FloatOps.mul64 0x7FF0000000000001 0x3FF0000000000000 = 0x7FF8000000000001%Z.
Proof. exact FloatOps.mul64_nan_payload. Qed.

(** ** The error monad *)

(** Mapping a function over a list in the error monad ([mmap]) preserves
    the length of the list. *)
Theorem mmap_length:
  forall (A B : Type) (f : A -> res B) l l', mmap f l = OK l' -> length l' = length l.
Proof. exact Errors.mmap_length. Qed.

(** ** Systems of nodes (DESIGN.md section 10) *)

(** A link between two nodes: when the two nodes meet their data delivery
    specification (T2) and the link is well formed ([System.link_ok],
    decided per system: one graph name for the two topics, the relations
    and the leaf the models', a scalar through no bounded sequence), then in
    every pair of runs of the two programs, under the transport assumption
    ([System.delivered_from]: the newest message the subscriber received is
    one the publisher sent) and with the input kept fresh, the subscriber's
    controller receives exactly the field the publisher's controller
    computed in the cycle whose message was delivered ([System.link_holds]). *)
Theorem system_link:
  forall gA gB mA pA mB pB tpA o tpB ir,
  DDC.node_ddc mA pA -> DDC.node_ddc mB pB ->
  System.link_ok gA mA tpA o gB mB tpB ir = true ->
  System.link_holds mA pA tpA o mB pB tpB ir.
Proof. exact System.system_link. Qed.

(** A chain of nodes: when every node meets T2, every link between
    consecutive nodes is well formed and the last node's output relations
    are ([System.chain_ok]), then for any runs of all the chain's programs
    there is one T2 decomposition per node along which every link holds
    and the last node publishes what its controller computed
    ([System.chain_holds]). *)
Theorem chain_runs:
  forall ns ls outs, System.chain_ok ns ls outs -> System.chain_holds ns ls outs.
Proof. exact System.chain_runs. Qed.

(** Composed along a chain: for any choice of one link per pair of
    consecutive nodes, each node's input at each cycle is the upstream
    controller's output at the delivered cycle, back to the external
    input, and the last node publishes its controller's output
    ([System.chain_composed]). *)
Theorem chain_run_value:
  forall ns ls outs co (pick : nat -> System.clink), System.chain_holds ns ls outs -> In co outs ->
  (forall l, (S l < length ns)%nat -> In (pick l) ls /\ System.cl_from (pick l) = l) ->
  System.chain_composed ns co pick.
Proof. exact System.chain_run_value. Qed.
