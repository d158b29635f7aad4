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
    [Controller_Y], the clock globals [c_new], [c_rcvd], [c_time]) are
    the interface of the generated C code (DESIGN.md, section 5), so the
    specifications refer to them: they are the only definitions taken
    from [Wellformed].  Nothing is taken from the generator ([Generator]
    is not loaded): the constants of the specification (the largest
    [unsigned int] and [unsigned long long], the timeout in nanoseconds
    from the model's milliseconds) are stated here, and the proofs show
    that the generator's agree with them ([Gluefacts.uint_max_agrees],
    [Gluefacts.ulong_max_agrees], [Gluefacts.timeout_ns_agrees]). *)

From Coq Require Import String List ZArith Bool Lia.
From ROSGen Require Import Errors Syntax Values Memory Environment Semantics NodeModel.
From ROSGen Require Wellformed.
Import Wellformed (msg_var, callback_name, input_glue_name, output_glue_name,
                   new_var, rcvd_var, time_var).
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

(** Going from [mm] to [mm'] replaced the values of the globals [x1],
    ..., [xn] by [mv1], ..., [mvn], in this order, and changed nothing
    else. *)
Inductive globals_changed (p : program) : mem -> mem -> list (ident * mval) -> Prop :=
  | globals_changed_nil: forall mm,
      globals_changed p mm mm []
  | globals_changed_cons: forall mm mm1 mm' x mv l,
      only_global_changed p mm mm1 x mv -> globals_changed p mm1 mm' l ->
      globals_changed p mm mm' ((x, mv) :: l).

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

(** ** Time and freshness (rule 4.12) *)

(** ROS time, in nanoseconds, as the glue holds it: an [unsigned long
    long] ([ros_now]'s value).  For the times of a real clock (from 0 to
    about 584 years) it is the time itself. *)
Definition clock (t : Z) : Z := norm_long Unsigned t.

(** The largest [unsigned long long], [2^64 - 1]. *)
Definition ulong_max : Z := 2 ^ 64 - 1.

(** The largest [unsigned int], [2^32 - 1]. *)
Definition uint_max : Z := 2 ^ 32 - 1.

(** The timeout of the topic with C name [c], in nanoseconds: the
    model's timeout in milliseconds ([nm_timeouts]) times [10^6]; [None]
    if the topic has no timeout. *)
Definition timeout_ns (m : node_model) (c : ident) : option Z :=
  match find_assoc c (nm_timeouts m) with
  | Some ms => Some (ms * 1000000)%Z
  | None => None
  end.

(** The age at time [now] of the newest message of a topic, received at
    [rcv] ([None]: no message yet), in nanoseconds: 0 if the clock went
    back, the largest [unsigned long long] if no message arrived. *)
Definition age_ns (rcv : option Z) (now : Z) : Z :=
  match rcv with
  | None => ulong_max
  | Some t => if (clock t <=? clock now)%Z then (clock now - clock t)%Z else 0%Z
  end.

(** A topic with C name [c] is stale at time [now] when it has a timeout
    and no message arrived, or its newest one is older than the
    timeout. *)
Definition stale (m : node_model) (c : ident) (rcv : option Z) (now : Z) : bool :=
  match timeout_ns m c with
  | Some t => match rcv with
              | None => true
              | Some _ => (t <? age_ns rcv now)%Z
              end
  | None => false
  end.

(** What the controller input of relation [ir] receives when the related
    field of the newest message is [v]: [v], unless the topic is stale and
    the input has a fallback value. *)
Definition fed_value (m : node_model) (ir : inrel) (v : val) (rcv : option Z) (now : Z) : val :=
  if stale m (ir_topic ir) rcv now
  then match find_assoc (ir_input ir) (nm_fallbacks m) with Some fv => fv | None => v end
  else v.

(** A derived input, from whether a message arrived since the previous
    cycle ([isnew]) and the receipt time of the newest one ([rcv]):
    [is_new], [received] (1 or 0), and [age_ms], the age in
    milliseconds, saturating at [2^32 - 1] (also when none arrived). *)
Definition derived_value (k : derived) (isnew : bool) (rcv : option Z) (now : Z) : val :=
  match k with
  | Dis_new => Vint (if isnew then 1 else 0)
  | Dreceived => Vint (match rcv with Some _ => 1 | None => 0 end)
  | Dage_ms => Vint (Z.min (age_ns rcv now / 1000000)%Z uint_max)
  end.

(** The clock globals of the timed topic [c] in memory [mm] hold
    [isnew] and [rcv]: the flag [c_new] is [isnew], the flag [c_rcvd]
    says whether a message arrived, and [c_time] holds its receipt time. *)
Definition clock_held (p : program) (mm : mem) (c : ident) (isnew : bool) (rcv : option Z) : Prop :=
  global_value p mm (new_var c) = Some (MVscalar (Vint (if isnew then 1 else 0)))
  /\ global_value p mm (rcvd_var c) = Some (MVscalar (Vint (match rcv with Some _ => 1 | None => 0 end)))
  /\ forall t, rcv = Some t -> global_value p mm (time_var c) = Some (MVscalar (Vlong (clock t))).

(** What a callback of the timed topic [c] writes into its clock when
    the time is [now]; nothing for a topic that is not timed. *)
Definition clock_update (m : node_model) (c : ident) (now : Z) : list (ident * mval) :=
  if is_timed m c
  then [(time_var c, MVscalar (Vlong (clock now))); (new_var c, MVscalar (Vint 1));
        (rcvd_var c, MVscalar (Vint 1))]
  else [].

(** ** Functions (theorem T1) *)

(** The message held by the global [s_msg] of a subscribed topic. *)
Definition global_msg (p : program) (mm : mem) (s : ident) : mval :=
  match global_value p mm (msg_var s) with Some v => v | None => MVscalar Vundef end.

(** [g] is [g0] with the leaves of [mv] that the node reads: at every
    leaf [lp] of the messages of topic [tp], [g] holds what [mv] holds if
    the node reads [lp] ([read_paths]: an input relation names it, or a
    stamp is copied from it), and what [g0] holds otherwise. *)
Definition reads_copied (m : node_model) (tp : topic) (mv g0 g : mval) : Prop :=
  forall lp q, resolve (nm_msgs m) (FTmsg (tp_msg tp)) lp = Some (FTprim q) ->
    mval_get g (path_steps lp)
    = mval_get (if is_read m (tp_cname tp) lp then mv else g0) (path_steps lp).

(** The value held by [Controller_U]. *)
Definition global_inputs (m : node_model) (p : program) (mm : mem) : mval :=
  match global_value p mm (nm_in_var m) with Some v => v | None => MVscalar Vundef end.

(** The leaf of [Controller_U] that an input relation feeds: the input
    field [In], or one element [Scan[i]] of an array input. *)
Definition input_leaf (ir : inrel) : Values.path := Sfield (ir_input ir) :: path_steps (ir_elem ir).

(** [u] is [u0] with the leaves of the direct input relations of topic
    [tp] (rule 4.16) taken from [mv]: the leaf of each such relation holds
    what [mv] holds at the relation's message leaf, and every path
    disjoint from all these leaves holds what [u0] holds. *)
Definition direct_copied (m : node_model) (tp : topic) (mv u0 u : mval) : Prop :=
  (forall ir, In ir (direct_of m (tp_cname tp)) ->
     mval_get u (input_leaf ir) = mval_get mv (path_steps (ir_path ir)))
  /\ (forall lp, (forall ir, In ir (direct_of m (tp_cname tp)) -> path_disjoint (input_leaf ir) lp) ->
        mval_get u lp = mval_get u0 lp).

(** The callback of a subscribed topic [tp] (the paper's Figure 10): called
    with a pointer to a block holding a message [mv] of the topic's type
    (a block that is not a global, as [ros_spinOnce] provides), it copies
    into the topic's global [c_msg] the leaves of [mv] that the glue
    keeps there ([read_paths]), and leaves the other leaves of [c_msg] as they were
    ([reads_copied]); it writes the leaves of its direct input relations
    (rule 4.16) into [Controller_U] and leaves the rest of
    [Controller_U] as it was ([direct_copied]); if the topic is timed, it
    records the time of the call ([ros_now()]: the message's receipt
    time) and sets the flags [c_new] and [c_rcvd]; it changes nothing
    else. *)
Definition callback_ddc (m : node_model) (p : program) (tp : topic) : Prop :=
  exists f,
     find_funct (globalenv p) (callback_name (tp_cname tp)) = Some (Internal f)
  /\ forall mm b mv,
       globals_typed p mm ->
       not_global p b ->
       get_block mm b = Some (Tstruct (tp_msg tp), mv) ->
       mval_has_type (prog_types p) (Tstruct (tp_msg tp)) mv ->
       quiet_call_at p (Internal f) [Vptr b []] mm
         (fun now mm' => exists g u,
             globals_changed p mm mm'
               ((msg_var (tp_cname tp), g) :: (nm_in_var m, u) :: clock_update m (tp_cname tp) now)
          /\ mval_has_type (prog_types p) (Tstruct (tp_msg tp)) g
          /\ reads_copied m tp mv (global_msg p mm (tp_cname tp)) g
          /\ mval_has_type (prog_types p) (Tstruct (nm_in_struct m)) u
          /\ direct_copied m tp mv (global_inputs m p mm) u).

(** [input_glue] (the paper's Figure 12): from any memory where the globals
    hold values of their types, and the clock of every timed topic [c]
    holds some [ck c], it writes a value [u] of the inputs' type into
    [Controller_U] in which the leaf of every input relation (an input
    field [In], or an element [Scan[i]] of an array input) equals the
    field of the global message of the topic that the relation names
    (or its fallback value if that topic is stale at the time [now] of
    the call: [fed_value]), and every derived input is exact at [now]
    ([derived_value]); then it clears the [c_new] flag of every timed
    topic; and it changes nothing else.  It does not copy the direct
    input relations (rule 4.16), whose leaves the callbacks wrote: they
    keep their values. *)
Definition input_glue_ddc (m : node_model) (p : program) : Prop :=
  exists f,
     find_funct (globalenv p) input_glue_name = Some (Internal f)
  /\ forall mm (ck : ident -> bool * option Z),
       globals_typed p mm ->
       (forall tp, In tp (timed m) -> clock_held p mm (tp_cname tp) (fst (ck (tp_cname tp))) (snd (ck (tp_cname tp)))) ->
       quiet_call_at p (Internal f) [] mm (fun now mm' =>
         exists u,
            globals_changed p mm mm'
              ((nm_in_var m, u) :: map (fun tp => (new_var (tp_cname tp), MVscalar (Vint 0))) (timed m))
         /\ mval_has_type (prog_types p) (Tstruct (nm_in_struct m)) u
         /\ (forall ir, In ir (glue_inrels m) ->
              exists g v,
                 global_value p mm (msg_var (ir_topic ir)) = Some g
              /\ mval_get g (path_steps (ir_path ir)) = Some (MVscalar v)
              /\ mval_get u (Sfield (ir_input ir) :: path_steps (ir_elem ir)) = Some (MVscalar (fed_value m ir v (snd (ck (ir_topic ir))) now)))
         /\ (forall dr, In dr (nm_drels m) ->
              mval_get u [Sfield (dr_input dr)]
              = Some (MVscalar (derived_value (dr_kind dr) (fst (ck (dr_topic dr))) (snd (ck (dr_topic dr))) now)))
         /\ (forall ir, In ir (nm_inrels m) -> is_direct m ir = true ->
              mval_get u (input_leaf ir) = mval_get (global_inputs m p mm) (input_leaf ir))).

(** The seconds a stamp holds at the ROS time [now] (rule 4.13): on
    ROS 1 ([uint32 sec]) the seconds of [now], modulo 2^32
    ([Environment.time_sec]); on ROS 2 ([int32 sec],
    [NodeModel.time_is_ros2]) the signed 32-bit reading of those same
    seconds, [norm_int I32 Signed]: the seconds themselves until 2038
    (2^31 s after 1970), then negative, wrapped modulo 2^32 (gcc's
    conversion of an [unsigned int] to an [int]).  Its nanoseconds are
    [time_nsec now] in the field [stamp_nsec m]: [nsec], ROS 2's
    [nanosec]. *)
Definition stamp_sec (m : node_model) (now : Z) : Z :=
  if time_is_ros2 (nm_msgs m) then norm_int I32 Signed (time_sec now) else time_sec now.
Definition stamp_nsec (m : node_model) : ident := time_nsec_field (nm_msgs m).

(** The message that a published topic [tp] carries when the controller's
    outputs are [y], the ROS time is [now] and the subscribed topic with
    C name [s] holds the message [g s]: a message of the topic's type in
    which every field that an output relation of the topic names holds
    the related output field of [y], the stamp, if the topic has one
    (rule 4.13), holds the seconds and nanoseconds of [now] ([stamp_sec],
    [stamp_nsec]: on ROS 2, the seconds as a signed 32-bit number), or,
    for a stamp copied from a subscribed topic [s], the [sec] and [nsec]
    ([nanosec] on ROS 2) of the source field of [g s], every constant string of the topic (rule
    4.14) holds its bytes ([len] their number, [data[i]] the [i]-th),
    and every other scalar field is zero: [truncated], and the bytes of
    a string past its length, among them. *)
Definition published_value (m : node_model) (y : mval) (now : Z) (g : ident -> mval)
                           (tp : topic) (mv : mval) : Prop :=
  mval_has_type (composites m) (Tstruct (tp_msg tp)) mv
  /\ (forall o, In o (nm_outrels m) -> or_topic o = tp_cname tp ->
        exists v, mval_get y (Sfield (or_output o) :: path_steps (or_elem o)) = Some (MVscalar v)
               /\ mval_get mv (path_steps (or_path o)) = Some (MVscalar v))
  /\ (forall sp, find_assoc (tp_cname tp) (nm_stamps m) = Some sp ->
        match find_assoc (tp_cname tp) (nm_stamp_from m) with
        | None =>
            mval_get mv (path_steps (sp ++ [PField "sec"%string])) = Some (MVscalar (Vint (stamp_sec m now)))
         /\ mval_get mv (path_steps (sp ++ [PField (stamp_nsec m)])) = Some (MVscalar (Vint (time_nsec now)))
        | Some (s, sp') =>
            mval_get mv (path_steps (sp ++ [PField "sec"%string]))
            = mval_get (g s) (path_steps (sp' ++ [PField "sec"%string]))
         /\ mval_get mv (path_steps (sp ++ [PField (stamp_nsec m)]))
            = mval_get (g s) (path_steps (sp' ++ [PField (stamp_nsec m)]))
        end)
  /\ (forall sp bs, In (tp_cname tp, (sp, bs)) (nm_strings m) ->
        mval_get mv (path_steps (sp ++ [PField "len"%string])) = Some (MVscalar (Vint (Z.of_nat (length bs))))
     /\ forall i b, nth_error bs i = Some b ->
          mval_get mv (path_steps (sp ++ [PField "data"%string; PIndex (Z.of_nat i)])) = Some (MVscalar (Vint b)))
  /\ (forall lp q, resolve (nm_msgs m) (FTmsg (tp_msg tp)) lp = Some (FTprim q) ->
        (forall o, In o (nm_outrels m) -> or_topic o = tp_cname tp -> or_path o <> lp) ->
        (forall sp, find_assoc (tp_cname tp) (nm_stamps m) = Some sp ->
           lp <> sp ++ [PField "sec"%string] /\ lp <> sp ++ [PField (stamp_nsec m)]) ->
        (forall sp bs, In (tp_cname tp, (sp, bs)) (nm_strings m) ->
           lp <> sp ++ [PField "len"%string]
        /\ forall i, (i < length bs)%nat -> lp <> sp ++ [PField "data"%string; PIndex (Z.of_nat i)]) ->
        mval_get mv (path_steps lp) = Some (zero_mval (composites m) (ctype_of_prim q))).

(** [output_glue_c(&cmd)] for a published topic [tp]: called with a
    pointer to a block (not a global) holding an object of the topic's
    type, initialised or not, it writes there the message that the
    outputs [y] held by [Controller_Y], the world's time and the global
    messages call for, and changes nothing else. *)
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
         /\ published_value m y now (global_msg p mm) tp mv
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

(** The arrivals [msgs] of one spin that the callback of topic [tp]
    receives: those on its topic that its queue keeps (the newest
    [tp_queue tp], all if 0), except the messages that a sequence with
    policy "reject" longer than its maximum makes the node drop
    ([Environment.too_long]: dropped after the queue, so that a rejected
    message may have pushed an accepted one out of it). *)
Fixpoint received_on (m : node_model) (tp : topic) (msgs : list arrival) : list arrival :=
  match msgs with
  | [] => []
  | a :: rest =>
      (if topic_eqb (ar_topic a) (tp_name tp)
          && (Nat.eqb (tp_queue tp) 0 || Nat.ltb (count_topic (tp_name tp) rest) (tp_queue tp))
          && negb (too_long (composites m) (Tstruct (tp_msg tp)) (ar_msg a))
       then [a] else []) ++ received_on m tp rest
  end.

Lemma last_on_app:
  forall name l1 l2,
  last_on name (l1 ++ l2) = match last_on name l2 with Some v => Some v | None => last_on name l1 end.
Proof.
  induction l1 as [|a l1 IH]; intros l2; simpl.
  - destruct (last_on name l2); auto.
  - rewrite IH. destruct (last_on name l2); auto.
Qed.

Lemma last_on_none_count:
  forall name l, last_on name l = None -> count_topic name l = O.
Proof.
  induction l as [|a l IH]; simpl; intros H; auto.
  destruct (last_on name l); try discriminate.
  unfold topic_eqb. destruct (string_dec (ar_topic a) name); try discriminate. rewrite IH; auto.
Qed.

(** Without a message too long for policy "reject", a queue of at least 1
    hands the callback the newest arrival on its topic. *)
Lemma received_on_all:
  forall m tp msgs, (1 <= tp_queue tp)%nat ->
  (forall a, In a msgs -> ar_topic a = tp_name tp -> too_long (composites m) (Tstruct (tp_msg tp)) (ar_msg a) = false) ->
  last_on (tp_name tp) (received_on m tp msgs) = last_on (tp_name tp) msgs.
Proof.
  intros m tp msgs Hq; induction msgs as [|a rest IH]; intros NT; simpl; auto.
  rewrite last_on_app, IH by (intros a' H' E'; apply NT; simpl; auto).
  destruct (last_on (tp_name tp) rest) as [v|] eqn:Lr; auto.
  apply last_on_none_count in Lr. rewrite Lr.
  unfold topic_eqb. destruct (string_dec (ar_topic a) (tp_name tp)) as [E|E]; simpl; auto.
  replace (Nat.eqb (tp_queue tp) 0 || Nat.ltb 0 (tp_queue tp)) with true
    by (symmetry; apply orb_true_iff; right; apply Nat.ltb_lt; lia).
  rewrite (NT a (or_introl eq_refl) E). simpl. destruct (string_dec (ar_topic a) (tp_name tp)); congruence.
Qed.

(** The newest message that the callback of topic [tp] received up to the
    [i]-th spin, if any.  Without sequences of policy "reject", with a
    queue of at least 1, this is the newest raw arrival on the topic
    ([newest_arrival_raw]: that the queues keep the newest message is
    part of what T2 proves). *)
Definition newest_arrival {CS : Type} (m : node_model) (ctx : ros_context CS) (tp : topic) (i : nat)
  : option arrival :=
  last_on (tp_name tp) (flat_map (fun j => received_on m tp (ctx_arrivals ctx j)) (seq 0 (S i))).

Lemma newest_arrival_raw:
  forall CS m (ctx : ros_context CS) tp i, (1 <= tp_queue tp)%nat ->
  (forall k a, In a (ctx_arrivals ctx k) -> ar_topic a = tp_name tp ->
     too_long (composites m) (Tstruct (tp_msg tp)) (ar_msg a) = false) ->
  newest_arrival m ctx tp i = last_on (tp_name tp) (arrivals_upto ctx i).
Proof.
  intros CS m ctx tp i Hq NT. unfold newest_arrival, arrivals_upto.
  induction (seq 0 (S i)) as [|j js IH]; simpl; auto.
  rewrite !last_on_app, IH. destruct (last_on (tp_name tp) (flat_map (ctx_arrivals ctx) js)); auto.
  apply received_on_all; auto. intros a H E. apply (NT j a H E).
Qed.

(** The message that the callback of topic [tp] receives for the
    arrival [a]: its bounded sequences converted ([Environment.clamp]). *)
Definition converted (m : node_model) (tp : topic) (a : arrival) : mval :=
  clamp (composites m) (Tstruct (tp_msg tp)) (ar_msg a).

(** The model path [sp] leads, in messages of topic [tp], through no
    other bounded sequence, to a bounded sequence: a struct [id] named
    [ros_seq_...] or [ros_string...] of [len], [truncated] and [data[n]],
    whose elements have the scalar type [t]. *)
Definition bounded_at (m : node_model) (tp : topic) (sp : path) (id : ident) (n : Z) (t : type) : Prop :=
     unbounded_path (composites m) (Tstruct (tp_msg tp)) (path_steps sp) = true
  /\ type_at (composites m) (Tstruct (tp_msg tp)) (path_steps sp) = Some (Tstruct id)
  /\ bounded_name id = true
  /\ struct_members (composites m) id
     = Some [("len"%string, Tint I32 Unsigned); ("truncated"%string, Tint I8 Unsigned); ("data"%string, Tarray t n)]
  /\ is_scalar_type t = true.

(** [v] holds, at the bounded sequence [sp] (capacity [n], elements of
    type [t]) whose length in [mv] is [l], what [Environment.clamp] makes
    of it: the length capped at [n], whether the sequence was longer than
    [n], and the first [min(l, n)] elements of [mv] followed by zeros. *)
Definition clamped_at (v mv : mval) (sp : path) (n : Z) (t : type) (l : Z) : Prop :=
     mval_get v (path_steps (sp ++ [PField "len"%string])) = Some (MVscalar (Vint (Z.min l n)))
  /\ mval_get v (path_steps (sp ++ [PField "truncated"%string]))
     = Some (MVscalar (Vint (if (n <? l)%Z then 1 else 0)))
  /\ (forall j, (0 <= j < n)%Z ->
        mval_get v (path_steps (sp ++ [PField "data"%string; PIndex j]))
        = if (j <? Z.min l n)%Z then mval_get mv (path_steps (sp ++ [PField "data"%string; PIndex j]))
          else Some (MVscalar (zero_val t))).

(** What the callback receives of a bounded sequence at the model path
    [sp] of a message: [clamped_at].  With [input_values] (T2), this is
    what an input related to [sp.len], [sp.truncated] or [sp.data[j]]
    receives. *)
Lemma converted_sequence:
  forall m tp a sp id n t l,
  mval_has_type (composites m) (Tstruct (tp_msg tp)) (ar_msg a) ->
  bounded_at m tp sp id n t ->
  mval_get (ar_msg a) (path_steps (sp ++ [PField "len"%string])) = Some (MVscalar (Vint l)) ->
  clamped_at (converted m tp a) (ar_msg a) sp n t l.
Proof.
  intros m tp a sp id n t l T (U & Ty & B & SM & St) Gl. unfold clamped_at. set (v := converted m tp a).
  destruct (mval_get_has_type _ _ _ _ _ T Ty) as (sv & Gs & Ts).
  assert (C: mval_get v (path_steps sp) = Some (clamp (composites m) (Tstruct id) sv))
    by (unfold v, converted; apply clamp_get; auto).
  unfold path_steps in *. rewrite !map_app in *. cbn [map step_of_pstep] in *.
  rewrite mval_get_app, Gs in Gl.
  destruct (clamp_bounded (composites m) id sv l n t B SM St Ts Gl) as (L & Tr & D).
  rewrite !mval_get_app, C. split; [exact L|split; [exact Tr|]].
  intros j Hj. rewrite !map_app. cbn [map step_of_pstep].
  rewrite !mval_get_app, C, (D j Hj), Gs. reflexivity.
Qed.

(** The same for a bounded sequence of any element type ([bounded_at]
    without its last condition): a sequence of messages, whose elements
    may hold sequences too.  The callback receives each of the first
    [min(l, n)] elements converted ([Environment.clamp]: its own
    sequences capped in turn), then elements of zeros. *)
Definition bounded_elems_at (m : node_model) (tp : topic) (sp : path) (id : ident) (n : Z) (t : type) : Prop :=
     unbounded_path (composites m) (Tstruct (tp_msg tp)) (path_steps sp) = true
  /\ type_at (composites m) (Tstruct (tp_msg tp)) (path_steps sp) = Some (Tstruct id)
  /\ bounded_name id = true
  /\ struct_members (composites m) id
     = Some [("len"%string, Tint I32 Unsigned); ("truncated"%string, Tint I8 Unsigned); ("data"%string, Tarray t n)].

Lemma converted_sequence_elems:
  forall m tp a sp id n t l,
  mval_has_type (composites m) (Tstruct (tp_msg tp)) (ar_msg a) ->
  bounded_elems_at m tp sp id n t ->
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
Proof.
  intros m tp a sp id n t l T (U & Ty & B & SM) Gl v.
  destruct (mval_get_has_type _ _ _ _ _ T Ty) as (sv & Gs & Ts).
  assert (C: mval_get v (path_steps sp) = Some (clamp (composites m) (Tstruct id) sv))
    by (unfold v, converted; apply clamp_get; auto).
  unfold path_steps in *. rewrite !map_app in *. cbn [map step_of_pstep] in *.
  rewrite mval_get_app, Gs in Gl.
  destruct (clamp_bounded_elems (composites m) id sv l n t B SM Ts Gl) as (L & Tr & D).
  rewrite !mval_get_app, C. split; [exact L|split; [exact Tr|]].
  intros j Hj. rewrite !map_app. cbn [map step_of_pstep].
  rewrite !mval_get_app, C, (D j Hj), Gs. reflexivity.
Qed.

(** The newest message that arrived on topic [tp] up to the [i]-th spin,
    as its callback receives it, or the zero message if none did. *)
Definition newest {CS : Type} (m : node_model) (ctx : ros_context CS) (tp : topic) (i : nat) : mval :=
  match newest_arrival m ctx tp i with
  | Some a => converted m tp a
  | None => zero_mval (composites m) (Tstruct (tp_msg tp))
  end.

(** The newest message, up to the [i]-th spin, of the topic with C name
    [s]. *)
Definition newest_by {CS : Type} (m : node_model) (ctx : ros_context CS) (i : nat) (s : ident) : mval :=
  match find_topic (nm_topics m) s with Some tp => newest m ctx tp i | None => MVscalar Vundef end.

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

(** The receipt time of the newest message on topic [tp] up to the
    [i]-th spin, if any. *)
Definition newest_time {CS : Type} (m : node_model) (ctx : ros_context CS) (tp : topic) (i : nat)
  : option Z :=
  option_map ar_time (newest_arrival m ctx tp i).

(** Whether the callback of topic [tp] received a message in the [i]-th
    spin, that is since the previous cycle. *)
Definition arrived {CS : Type} (m : node_model) (ctx : ros_context CS) (tp : topic) (i : nat) : bool :=
  match last_on (tp_name tp) (received_on m tp (ctx_arrivals ctx i)) with Some _ => true | None => false end.

(** The inputs [u] handed to the controller in cycle [i]: a value of the
    inputs' type in which every input field [In] (every element [Scan[i]]
    of an array input) holds the field, named by its input relation, of
    the newest message received so far
    on the relation's topic (zero if none yet) -- unless that topic is
    stale at the cycle's time [ctx_time ctx (S i)] and [In] has a
    fallback value, which it then holds ([fed_value], rule 4.12); and
    every derived input holds what [derived_value] says of its topic at
    the cycle's time. *)
Definition input_values {CS : Type} (m : node_model) (ctx : ros_context CS) (i : nat) (u : mval) : Prop :=
  mval_has_type (composites m) (Tstruct (nm_in_struct m)) u
  /\ (forall ir, In ir (nm_inrels m) ->
       exists tp v,
          In tp (subscribed m)
       /\ tp_cname tp = ir_topic ir
       /\ mval_get (newest m ctx tp i) (path_steps (ir_path ir)) = Some (MVscalar v)
       /\ mval_get u (Sfield (ir_input ir) :: path_steps (ir_elem ir))
          = Some (MVscalar (fed_value m ir v (newest_time m ctx tp i) (ctx_time ctx (S i)))))
  /\ (forall dr, In dr (nm_drels m) ->
       exists tp,
          In tp (subscribed m)
       /\ tp_cname tp = dr_topic dr
       /\ mval_get u [Sfield (dr_input dr)]
          = Some (MVscalar (derived_value (dr_kind dr) (arrived m ctx tp i) (newest_time m ctx tp i) (ctx_time ctx (S i))))).

(** What ROS carries when the glue publishes the message [mv] on topic
    [tp]: [mv] with its bounded sequences converted as on receipt
    ([Environment.clamp]: the length capped at the maximum [N], the first
    [min(len, N)] elements, zeros after; the wrapper sends these
    elements).  The identity on messages without bounded sequences. *)
Definition sent (m : node_model) (tp : topic) (mv : mval) : mval :=
  clamp (composites m) (Tstruct (tp_msg tp)) mv.

(** A scalar field of a published message reached through no bounded
    sequence is sent as the glue wrote it. *)
Lemma sent_scalar:
  forall m tp mv lp t x,
  mval_has_type (composites m) (Tstruct (tp_msg tp)) mv ->
  unbounded_path (composites m) (Tstruct (tp_msg tp)) (path_steps lp) = true ->
  type_at (composites m) (Tstruct (tp_msg tp)) (path_steps lp) = Some t ->
  mval_get mv (path_steps lp) = Some (MVscalar x) ->
  mval_get (sent m tp mv) (path_steps lp) = Some (MVscalar x).
Proof.
  intros m tp mv lp t x T U Ty G.
  unfold sent. rewrite (clamp_get _ _ _ _ t _ T U Ty G). reflexivity.
Qed.

(** A bounded sequence of a published message, at the model path [sp]
    (reached through no other bounded sequence), is sent with the length
    that the glue wrote capped at the maximum [n], and its first
    [min(len, n)] elements followed by zeros: with T2's
    [published_value], a published sequence carries exactly the first
    [min(len, n)] of the elements that the related outputs give, [len]
    the related length output. *)
Lemma sent_sequence:
  forall m tp mv sp id n t l,
  mval_has_type (composites m) (Tstruct (tp_msg tp)) mv ->
  bounded_at m tp sp id n t ->
  mval_get mv (path_steps (sp ++ [PField "len"%string])) = Some (MVscalar (Vint l)) ->
  clamped_at (sent m tp mv) mv sp n t l.
Proof.
  intros m tp mv sp id n t l T B Gl.
  exact (converted_sequence m tp (mkarrival "" mv 0) sp id n t l T B Gl).
Qed.

(** The events of publishing [mvs] on the topics [tps]. *)
Definition publish_events (m : node_model) (tps : list topic) (mvs : list mval) : trace :=
  map (fun tm => Epublish (tp_name (fst tm)) (sent m (fst tm) (snd tm))) (combine tps mvs).

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
     evs = Estep u y :: publish_events m (published m) mvs ++ [Esleep (nm_period_ms m)]
  /\ input_values m ctx i u
  /\ ctx_step ctx s u = (s', y)
  /\ Forall2 (published_value m y (ctx_time ctx (S i)) (newest_by m ctx i)) (published m) mvs.

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

(** [node_ddc] on the environments of one target (rule 4.17): what the
    per-node file states of the target it was generated for
    ([<node>_ddc_target]).  [node_ddc] quantifies over every context, so
    it holds for both ([node_ddc_on_target]). *)
Definition node_ddc_on (tg : target) (m : node_model) (p : program) : Prop :=
  forall (CS : Type) (ctx : ros_context CS) (n : nat),
  ctx_target ctx = tg -> arrivals_wt m ctx -> controller_wt m ctx ->
     (exists t, program_behaves p ctx n t)
  /\ (forall t, program_behaves p ctx n t -> run_ok m ctx n t).

Lemma node_ddc_on_target: forall tg m p, node_ddc m p -> node_ddc_on tg m p.
Proof. intros tg m p H CS ctx n _. apply H. Qed.
