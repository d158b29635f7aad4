(** * Data delivery correctness: the specifications *)

(** This file states what it means for a program to deliver the data of a
    node model correctly, in terms of the semantics of [Semantics] only:
    it does not look at the statements of the program, only at what
    running it does.  It contains definitions and no proof.

    - Section "Functions" gives the paper's per-function specifications
      (Figures 10 and 12, and the output glue): [callback_ddc],
      [input_glue_ddc], [output_glue_ddc].  They are proved for every
      generated program in [Glueproof] (theorem T1).
    - Section "Nodes" gives the whole-node property [node_ddc]: in every
      environment, the node runs to completion for any number [n] of
      cycles; its trace starts with the initialisation of the controller
      and the registrations of the model's topics (names, message
      structs, queue sizes, in model order: [start_events]), and every
      cycle of its trace hands to the controller the related fields of
      the newest messages received so far, publishes the related fields
      of the controller's outputs and ends with a sleep of the model's
      period ([cycle_ok], [run_ok]).  It is proved for every generated
      program in [Loopproof] (theorem T2).

    The names of the generated functions and globals ([c_callback],
    [c_msg], [input_glue], [output_glue_c], [Controller_U],
    [Controller_Y]) are the interface of the generated C code
    (DESIGN.md, section 5), so the specifications refer to them. *)

From Coq Require Import String List ZArith Bool.
From ROSGen Require Import Errors Syntax Values Memory Environment Semantics NodeModel Wellformed Generator.
Import ListNotations.

(** ** Paths of the model and paths of the memory *)

(** A field selection [.f] of the model is the memory step [Sfield f], an
    array subscript [[i]] is [Sindex i]. *)
Definition step_of_pstep (s : pstep) : step :=
  match s with
  | PField f => Sfield f
  | PIndex i => Sindex i
  end.

(** [twist.linear.x] is [[Sfield "twist"; Sfield "linear"; Sfield "x"]]. *)
Definition path_steps (p : NodeModel.path) : Values.path := map step_of_pstep p.

(** ** Shapes of memory values *)

(** The shape of a value: the same structs (field names) and arrays
    (lengths), every scalar replaced by [Vundef].  A block whose value has
    the shape [undef_mval ce ty] holds an object of type [ty], initialised
    or not (an uninitialised local has exactly that value). *)
Fixpoint mval_shape (mv : mval) : mval :=
  match mv with
  | MVscalar _ => MVscalar Vundef
  | MVstruct fs => MVstruct (map (fun fv => (fst fv, mval_shape (snd fv))) fs)
  | MVarray es => MVarray (map mval_shape es)
  end.

(** ** Memories *)

(** The value of the global variable [x] of [p] in memory [mm]. *)
Definition global_value (p : program) (mm : mem) (x : ident) : option mval :=
  match find_var (globalenv p) x with
  | Some (b, _) =>
      match get_block mm b with
      | Some (_, mv) => Some mv
      | None => None
      end
  | None => None
  end.

(** Every global variable of [p] is live in [mm] and holds a value of its
    type. *)
Definition globals_typed (p : program) (mm : mem) : Prop :=
  forall x b ty, find_var (globalenv p) x = Some (b, ty) ->
  exists mv, get_block mm b = Some (ty, mv) /\ mval_has_type (prog_types p) ty mv.

(** Block [b] is not the block of a global variable of [p]. *)
Definition not_global (p : program) (b : block) : Prop :=
  forall x bx tx, find_var (globalenv p) x = Some (bx, tx) -> bx <> b.

(** Going from [mm] to [mm'] changed at most block [b]: every other block
    is as it was, and no block was allocated. *)
Definition unchanged_except (mm mm' : mem) (b : block) : Prop :=
  mem_next mm' = mem_next mm
  /\ forall b', b' <> b -> get_block mm' b' = get_block mm b'.

(** Going from [mm] to [mm'] replaced the value of the global [x] by [mv]
    and changed nothing else. *)
Definition only_global_changed (p : program) (mm mm' : mem) (x : ident) (mv : mval) : Prop :=
  exists b ty,
     find_var (globalenv p) x = Some (b, ty)
  /\ get_block mm' b = Some (ty, mv)
  /\ unchanged_except mm mm' b.

(** Calling [fd] with arguments [args] in memory [mm] terminates, in every
    environment and world; and every such run emits no event, leaves the
    world unchanged, returns nothing ([Vundef]: a [void] function) and
    ends in a memory satisfying [post]. *)
Definition quiet_call (p : program) (fd : fundef) (args : list val) (mm : mem)
                      (post : mem -> Prop) : Prop :=
  forall (CS : Type) (ctx : ros_context CS) (w : world CS),
     (exists t mm' w' v, eval_funcall ctx (globalenv p) mm w fd args t mm' w' v)
  /\ (forall t mm' w' v, eval_funcall ctx (globalenv p) mm w fd args t mm' w' v ->
        t = [] /\ w' = w /\ v = Vundef /\ post mm').

(** The same for a function whose effect depends on the time the world
    gives [ros_now] and the time functions: [post] is given that time. *)
Definition quiet_call_at (p : program) (fd : fundef) (args : list val) (mm : mem)
                         (post : Z -> mem -> Prop) : Prop :=
  forall (CS : Type) (ctx : ros_context CS) (w : world CS),
     (exists t mm' w' v, eval_funcall ctx (globalenv p) mm w fd args t mm' w' v)
  /\ (forall t mm' w' v, eval_funcall ctx (globalenv p) mm w fd args t mm' w' v ->
        t = [] /\ w' = w /\ v = Vundef /\ post (w_time w) mm').

(** ** Functions (theorem T1) *)

(** The callback of a subscribed topic [tp] (the paper's Figure 10): called
    with a pointer to a block holding a message [mv] of the topic's type
    (a block that is not a global, as [ros_spinOnce] provides), it copies
    the whole message into the topic's global [c_msg], and changes nothing
    else. *)
Definition callback_ddc (m : node_model) (p : program) (tp : topic) : Prop :=
  exists f,
     find_funct (globalenv p) (callback_name (tp_cname tp)) = Some (Internal f)
  /\ forall mm b mv,
       globals_typed p mm ->
       not_global p b ->
       get_block mm b = Some (Tstruct (tp_msg tp), mv) ->
       mval_has_type (prog_types p) (Tstruct (tp_msg tp)) mv ->
       quiet_call p (Internal f) [Vptr b []] mm
         (fun mm' => only_global_changed p mm mm' (msg_var (tp_cname tp)) mv).

(** [input_glue] (the paper's Figure 12): from any memory where the globals
    hold values of their types, it writes a value [u] of the inputs' type
    into [Controller_U] in which every input field [In] equals the field of
    the global message of the topic that the input relation of [In]
    names, and changes nothing else. *)
Definition input_glue_ddc (m : node_model) (p : program) : Prop :=
  exists f,
     find_funct (globalenv p) input_glue_name = Some (Internal f)
  /\ forall mm,
       globals_typed p mm ->
       quiet_call p (Internal f) [] mm (fun mm' =>
         exists u,
            only_global_changed p mm mm' (nm_in_var m) u
         /\ mval_has_type (prog_types p) (Tstruct (nm_in_struct m)) u
         /\ forall ir, In ir (nm_inrels m) ->
              exists g v,
                 global_value p mm (msg_var (ir_topic ir)) = Some g
              /\ mval_get g (path_steps (ir_path ir)) = Some (MVscalar v)
              /\ mval_get u [Sfield (ir_input ir)] = Some (MVscalar v)).

(** The message that a published topic [tp] carries when the controller's
    outputs are [y] and the ROS time is [now]: a message of the topic's
    type in which every field that an output relation of the topic names
    holds the related output field of [y], the stamp, if the topic has
    one (rule 4.13), holds the [sec] and [nsec] of [now], and every other
    scalar field is zero. *)
Definition published_value (m : node_model) (y : mval) (now : Z) (tp : topic) (mv : mval) : Prop :=
  mval_has_type (composites m) (Tstruct (tp_msg tp)) mv
  /\ (forall o, In o (nm_outrels m) -> or_topic o = tp_cname tp ->
        exists v, mval_get y [Sfield (or_output o)] = Some (MVscalar v)
               /\ mval_get mv (path_steps (or_path o)) = Some (MVscalar v))
  /\ (forall sp, find_assoc (tp_cname tp) (nm_stamps m) = Some sp ->
        mval_get mv (path_steps (sp ++ [PField "sec"%string])) = Some (MVscalar (Vint (time_sec now)))
     /\ mval_get mv (path_steps (sp ++ [PField "nsec"%string])) = Some (MVscalar (Vint (time_nsec now))))
  /\ (forall lp q, resolve (nm_msgs m) (FTmsg (tp_msg tp)) lp = Some (FTprim q) ->
        (forall o, In o (nm_outrels m) -> or_topic o = tp_cname tp -> or_path o <> lp) ->
        (forall sp, find_assoc (tp_cname tp) (nm_stamps m) = Some sp ->
           lp <> sp ++ [PField "sec"%string] /\ lp <> sp ++ [PField "nsec"%string]) ->
        mval_get mv (path_steps lp) = Some (zero_mval (composites m) (ctype_of_prim q))).

(** [output_glue_c(&cmd)] for a published topic [tp]: called with a
    pointer to a block (not a global) holding an object of the topic's
    type, initialised or not, it writes there the message that the
    outputs [y] held by [Controller_Y] and the world's time call for, and
    changes nothing else. *)
Definition output_glue_ddc (m : node_model) (p : program) (tp : topic) : Prop :=
  exists f,
     find_funct (globalenv p) (output_glue_name (tp_cname tp)) = Some (Internal f)
  /\ forall mm b mv0 y,
       globals_typed p mm ->
       not_global p b ->
       get_block mm b = Some (Tstruct (tp_msg tp), mv0) ->
       mval_shape mv0 = undef_mval (prog_types p) (Tstruct (tp_msg tp)) ->
       global_value p mm (nm_out_var m) = Some y ->
       quiet_call_at p (Internal f) [Vptr b []] mm (fun now mm' =>
         exists mv,
            get_block mm' b = Some (Tstruct (tp_msg tp), mv)
         /\ published_value m y now tp mv
         /\ unchanged_except mm mm' b).

(** ** Nodes (theorem T2) *)

(** *** The newest message *)

(** The last arrival on the topic named [name] in [msgs], if any. *)
Fixpoint last_on (name : string) (msgs : list arrival) : option arrival :=
  match msgs with
  | [] => None
  | a :: rest =>
      match last_on name rest with
      | Some v => Some v
      | None => if string_dec (ar_topic a) name then Some a else None
      end
  end.

(** The messages that arrived up to the [i]-th call of [ros_spinOnce]
    (calls counted from 0), in arrival order. *)
Definition arrivals_upto {CS : Type} (ctx : ros_context CS) (i : nat) : list arrival :=
  flat_map (ctx_arrivals ctx) (seq 0 (S i)).

(** The newest arrival on topic [tp] up to the [i]-th spin, if any.
    This is defined from the raw arrivals, not from what the queues
    deliver: that the queues of size at least 1 always keep the newest
    message is part of what T2 proves. *)
Definition newest_arrival {CS : Type} (ctx : ros_context CS) (tp : topic) (i : nat) : option arrival :=
  last_on (tp_name tp) (arrivals_upto ctx i).

(** The newest message that arrived on topic [tp] up to the [i]-th spin,
    or the zero message if none did. *)
Definition newest {CS : Type} (m : node_model) (ctx : ros_context CS) (tp : topic) (i : nat) : mval :=
  match newest_arrival ctx tp i with
  | Some a => ar_msg a
  | None => zero_mval (composites m) (Tstruct (tp_msg tp))
  end.

(** *** The environments considered *)

(** Every message arriving on a subscribed topic is a value of the
    topic's message type. *)
Definition arrivals_wt {CS : Type} (m : node_model) (ctx : ros_context CS) : Prop :=
  forall k a tp,
  In a (ctx_arrivals ctx k) -> In tp (subscribed m) -> tp_name tp = ar_topic a ->
  mval_has_type (composites m) (Tstruct (tp_msg tp)) (ar_msg a).

(** The controller's step returns outputs of the outputs' type.  Nothing
    else is assumed about it: it is any function of its state and
    inputs. *)
Definition controller_wt {CS : Type} (m : node_model) (ctx : ros_context CS) : Prop :=
  forall s u, mval_has_type (composites m) (Tstruct (nm_out_struct m)) (snd (ctx_step ctx s u)).

(** *** One cycle *)

(** The inputs [u] handed to the controller in cycle [i]: a value of the
    inputs' type in which every input field [In] holds the field, named
    by the input relation of [In], of the newest message received so far
    on the relation's topic (zero if none yet). *)
Definition input_values {CS : Type} (m : node_model) (ctx : ros_context CS) (i : nat) (u : mval) : Prop :=
  mval_has_type (composites m) (Tstruct (nm_in_struct m)) u
  /\ forall ir, In ir (nm_inrels m) ->
       exists tp v,
          In tp (subscribed m)
       /\ tp_cname tp = ir_topic ir
       /\ mval_get (newest m ctx tp i) (path_steps (ir_path ir)) = Some (MVscalar v)
       /\ mval_get u [Sfield (ir_input ir)] = Some (MVscalar v).

(** The events of publishing [mvs] on the topics [tps]. *)
Definition publish_events (tps : list topic) (mvs : list mval) : trace :=
  map (fun tm => Epublish (tp_name (fst tm)) (snd tm)) (combine tps mvs).

(** Cycle [i] (from 0), started with controller state [s], emits the
    events [evs] and leaves the controller in state [s']: the controller
    is stepped once, from [s] to [s'], on the inputs [u] that
    [input_values] prescribes, giving outputs [y]; then each published
    topic of the model, in model order, publishes the message that
    [published_value] prescribes for [y] at the cycle's time
    [ctx_time ctx (S i)] (read when the [i]-th spin returned); then the
    cycle ends with a sleep of the model's period [nm_period_ms m]. *)
Definition cycle_ok {CS : Type} (m : node_model) (ctx : ros_context CS) (i : nat)
                    (s : CS) (evs : trace) (s' : CS) : Prop :=
  exists u y mvs,
     evs = Estep u y :: publish_events (published m) mvs ++ [Esleep (nm_period_ms m)]
  /\ input_values m ctx i u
  /\ ctx_step ctx s u = (s', y)
  /\ Forall2 (published_value m y (ctx_time ctx (S i))) (published m) mvs.

(** *** Before the first cycle *)

(** The registration of a subscribed topic: its ROS name, its message
    struct and its queue size. *)
Definition subscribe_event (tp : topic) : event := Esubscribe (tp_name tp) (tp_msg tp) (tp_queue tp).

(** The registration of a published topic, likewise. *)
Definition advertise_event (tp : topic) : event := Eadvertise (tp_name tp) (tp_msg tp) (tp_queue tp).

(** What a node does before its first cycle: it initialises the
    controller, then subscribes to each subscribed topic of the model, in
    model order, then advertises each published topic, in model order. *)
Definition start_events (m : node_model) : trace :=
  Einit :: map subscribe_event (subscribed m) ++ map advertise_event (published m).

(** *** Whole runs *)

(** The trace [t] of a run of [n] cycles is the start of the node
    ([start_events]: the controller's initialisation, the subscriptions
    and the advertisements) followed by the concatenation of [n] traces
    of correct cycles, the controller's states chained from its initial
    state. *)
Definition run_ok {CS : Type} (m : node_model) (ctx : ros_context CS) (n : nat) (t : trace) : Prop :=
  exists (s : nat -> CS) (evs : nat -> trace),
     s O = ctx_init ctx
  /\ t = start_events m ++ concat (map evs (seq 0 n))
  /\ forall i, (i < n)%nat -> cycle_ok m ctx i (s i) (evs i) (s (S i)).

(** Data delivery correctness of a node: in every environment with
    well-typed messages and controller outputs, and for every number [n]
    of cycles that [ros_ok] allows, the program terminates, and each of
    its behaviours (there is only one: the semantics is deterministic)
    is the node's start followed by a run of [n] correct cycles. *)
Definition node_ddc (m : node_model) (p : program) : Prop :=
  forall (CS : Type) (ctx : ros_context CS) (n : nat),
  arrivals_wt m ctx -> controller_wt m ctx ->
     (exists t, program_behaves p ctx n t)
  /\ (forall t, program_behaves p ctx n t -> run_ok m ctx n t).
