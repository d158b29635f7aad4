(** * The ROS environment model *)

(** This file says what the world outside the program does: what
    [ros_spinOnce] delivers (the subscriptions, the message queues and
    [deliverable]), what [ros_publish], [ros_ok], [ros_subscribe],
    [ros_advertise], [ros_rate_sleep], [Controller_initialize] and
    [Controller_step] mean, and what the events of a trace are.  Together
    with the C subset's syntax, values and memory, it is the part of the
    semantics that a reviewer must trust: the theorems (T1, T2) are only
    as meaningful as this model is faithful to roscpp and to the
    controller's C code.  It is kept in a file of its own so that it can be
    reviewed alone; the rest of the semantics ([Semantics]) only uses it
    through [external_call] and [spin_messages], and through the two
    places where [ros_spinOnce] runs the callbacks (the rule
    [eval_funcall_spinOnce] and the judgement [deliver] of [Semantics]:
    each delivered message is put in a fresh block, the callback is
    called with a pointer to it, the block is freed).

    A [ros_context CS] fixes everything the program cannot control:
    - [ctx_arrivals k]: the messages [(topic, value)] that arrive, in
      order, between the [k-1]-th and the [k]-th call of [ros_spinOnce]
      (calls counted from 0);
    - a controller: a state type [CS], an initial state [ctx_init] and a
      step function [ctx_step : CS -> mval -> CS * mval] that receives the
      whole value of the inputs global ([Controller_U]) and returns its new
      state and the new value of the outputs global ([Controller_Y]);
    - [ctx_target]: the target the node runs on, [Ros1] or [Ros2]
      (rule 4.17), which fixes what [ros_spinOnce] delivers.
    The number [n] of [true] answers of [ros_ok] is a parameter of
    [Semantics.program_behaves].

    The [world] is the part of the state that lives outside the program's
    memory: the subscriptions registered so far (topic, message struct,
    queue size, callback), the advertised topics, the number of spins so
    far, the remaining [true] answers of [ros_ok], and the controller's
    state.  The controller's state is [None] until [Controller_initialize]
    is called: the world of [initial_world] has no controller state at
    all, not [ctx_init].  The external functions act as follows:
    - [ros_init()]: nothing.
    - [ros_ok()]: returns 1 and consumes one [true] answer if one is left,
      otherwise returns 0.
    - [ros_time_sec()], [ros_time_nsec()]: the [sec] and [nsec] fields
      of that same time ([time_sec], [time_nsec]), as [unsigned int]s;
      no event.  The generated glue stamps published headers with them.
    - [ros_subscribe_T(cb)] ([EF_ros_subscribe topic msgty q]), with
      argument the function pointer [Vfptr cb]: registers the subscription
      [(topic, msgty, q, cb)] and emits [Esubscribe topic msgty q].
    - [ros_advertise_T()] ([EF_ros_advertise topic msgty q]): registers the
      topic as advertised and emits [Eadvertise topic msgty q].
    - [ros_spinOnce()]: takes the messages [ctx_arrivals k] ([k] the spin
      counter) and computes, on ROS 1, [deliverable subs msgs]: for each
      subscription, the messages of its topic, of which a queue of size
      [q] keeps the newest [q] ([q = 0]: unbounded, as in roscpp);
      messages of topics nobody subscribed to are dropped; arrival order
      is kept.  On ROS 2, [rcl_deliverable subs msgs]: for each
      subscription in registration order, the messages of its topic that
      a KEEP_LAST history of depth [q] holds (the newest [q]), oldest
      first; one subscription's after the other's.  Then, for each kept message in order, unless it holds a
      sequence of policy "reject" longer than its maximum ([accepted];
      such a message is dropped), a fresh block
      holding the message value (of type [struct msgty]), its bounded
      sequences converted ([delivered], [clamp]), is allocated,
      the callback is called with a pointer to it, and the block is freed
      ([deliver]).  Finally the spin counter is incremented.  It emits
      nothing itself (the callbacks may).
    - [ros_publish_T(&msg)] ([EF_ros_publish topic msgty]), with argument a
      pointer: the topic must have been advertised; the value at the
      pointer, its bounded sequences converted as on receipt ([clamp]:
      what the wrapper sends is the first [min(len, N)] elements), is
      emitted as the event [Epublish topic value].
    - [ros_rate_sleep()] ([EF_ros_rate_sleep period_ms]): emits
      [Esleep period_ms], which marks the end of a cycle of [period_ms]
      milliseconds.
    - [Controller_initialize()] ([EF_controller_initialize u y]): sets the
      controller state to [Some ctx_init] and emits [Einit].
    - [Controller_step()] ([EF_controller_step u y]): only defined once the
      controller is initialised (state [Some s]; on [None] the semantics is
      stuck); reads the whole value [uv] of the global [u], computes
      [(s', yv) := ctx_step s uv], stores [yv] into the global [y], sets
      the state to [Some s'] and emits [Estep uv yv].  If [yv] does not
      have the type of [y], the step is undefined (the semantics is
      stuck): the controller may only write its outputs, at their type.
      The step is also undefined unless [u] and [y] hold values of their
      declared types when it is called: like the C that Embedded Coder
      generates, the step reads its inputs as their types and writes its
      outputs member by member, so the glue must keep both globals well
      typed (T2 proves that it does; [ctrl/Link.v] needs it to run the
      generated step in their place).

    The trace of a run is the list of its events in the order they
    happen.

    What the program does to the world is observable in its trace: the
    controller's initialisation ([Einit]), every registration with its
    topic, message struct and queue size ([Esubscribe], [Eadvertise]),
    every step ([Estep]), every publication ([Epublish]) and every end of
    cycle with its period ([Esleep]).  Only [ros_init], [ros_ok] and
    [ros_spinOnce] emit nothing: [ros_ok]'s answers and what
    [ros_spinOnce] delivers are fixed by the context, and their effect on
    the program is seen through the steps and publications.

    Why the controller's state is absent before [Controller_initialize]
    (rather than starting at [ctx_init]): the Simulink-generated
    [Controller_step] reads state that only [Controller_initialize] sets
    up (in general, non-zero initial conditions of delays and
    integrators), so stepping an uninitialised controller has no meaning,
    and the model gives it none.  A program that steps the controller
    without initialising it first has no behaviour in which it does so,
    and the [Einit] event makes the initialisation visible even in runs
    that never step (zero cycles). *)

From Coq Require Import String List ZArith Bool Lia.
From ROSGen Require Import Syntax Values Memory.
Import ListNotations.

(** ** Events and traces *)

Inductive event : Type :=
  | Einit                              (**r [Controller_initialize] *)
  | Esubscribe (topic : string) (msgty : ident) (queue : nat)
      (**r [ros_subscribe_T]: subscription to [topic], messages [struct msgty],
           queue size [queue] *)
  | Eadvertise (topic : string) (msgty : ident) (queue : nat)
      (**r [ros_advertise_T]: advertisement of [topic], messages [struct msgty],
           queue size [queue] *)
  | Estep (u y : mval)                 (**r [Controller_step] read [u] and wrote [y] *)
  | Epublish (topic : string) (m : mval)  (**r message [m] published on [topic] *)
  | Esleep (period_ms : Z).            (**r [ros_rate_sleep]: end of a cycle of
                                            [period_ms] milliseconds *)

Definition trace := list event.

(** ** What the environment sees of the program *)

(** [Controller_step] reads and writes the globals whose names it is
    given, so the environment looks them up in the program's global
    environment ([Semantics.globalenv] builds it).

    The global environment: struct definitions, the block and type of
    each global variable, the definition of each function. *)
Record genv : Type := mkgenv {
  ge_comp : composite_env;
  ge_vars : list (ident * (block * type));
  ge_funs : list (ident * fundef)
}.

Definition find_var (ge : genv) (x : ident) : option (block * type) := find_assoc x (ge_vars ge).
Definition find_funct (ge : genv) (x : ident) : option fundef := find_assoc x (ge_funs ge).

(** ** The ROS environment model *)

(** A subscription, as registered by [ros_subscribe_T]. *)
Record subscription : Type := mksub {
  sub_topic : string;      (**r the topic *)
  sub_msgty : ident;       (**r the message struct *)
  sub_queue : nat;         (**r the queue size (0: unbounded) *)
  sub_callback : ident     (**r the callback function *)
}.

(** A message arrival: its topic, its value and the ROS time (in
    nanoseconds, as [ros::Time::toNSec] gives it) at which the node
    received it, which is what [ros::MessageEvent::getReceiptTime] tells
    the callback. *)
Record arrival : Type := mkarrival {
  ar_topic : string;
  ar_msg : mval;
  ar_time : Z
}.

(** ** Bounded sequences and strings *)

(** A ROS sequence ([T[]]) or [string] that the node carries is held in C
    by a struct named [ros_seq_...] or [ros_string...] of three members:
    [unsigned int len], [unsigned char truncated] and [T data[N]] ([T] the
    element type, [N] the sequence's maximum).  An arrival holds the ROS
    message as it was sent: in each bounded sequence, [len] is the
    sequence's real length (any [uint32]) and [data] its first [N]
    elements (the elements past [N] cannot matter to the node, so they
    are not represented; what [data] holds past [len] does not matter
    either).  The wrapper delivers it converted by [clamp] (policy
    "truncate"): [len] becomes [min(len, N)], [truncated] is 1 exactly
    when the sequence was longer than [N], and [data] keeps its first
    [min(len, N)] elements, every other element being zero.  Sequences
    are found by the struct names along the message's type, through
    nested structs and fixed-size arrays; the elements of a sequence of
    structs are converted in turn (their own sequences capped), and the
    missing ones are zero structs. *)
Definition reject_name (id : ident) : bool :=
  String.prefix "ros_rstring" id || String.prefix "ros_rseq_" id.

Definition bounded_name (id : ident) : bool :=
  String.prefix "ros_string" id || String.prefix "ros_seq_" id || reject_name id.

(** [clamp_seq ce members fs]: the conversion of a bounded struct of
    members [members] whose fields [fs] have already been converted
    (elements of a sequence of structs hold sequences too: each is
    converted first); [None] if it does not have the shape of one. *)
Definition clamp_seq (ce : composite_env) (members : list (ident * type)) (fs : list (ident * mval)) : option mval :=
  match members, fs with
  | [(_, Tint I32 Unsigned); (_, Tint I8 Unsigned); (_, Tarray t n)],
    [(fl, MVscalar (Vint l)); (ft, _); (fd, MVarray es)] =>
      let k := Z.min l n in
      Some (MVstruct [(fl, MVscalar (Vint k));
                      (ft, MVscalar (Vint (if (n <? l)%Z then 1 else 0)));
                      (fd, MVarray (firstn (Z.to_nat k) es
                                    ++ repeat (zero_mval ce t) (length es - Z.to_nat k)))])
  | _, _ => None
  end.

Fixpoint clamp (ce : composite_env) (ty : type) (mv : mval) {struct mv} : mval :=
  match mv with
  | MVscalar _ => mv
  | MVstruct fs =>
      match ty with
      | Tstruct id =>
          match struct_members ce id with
          | Some members =>
              let fs' := (fix go (ms : list (ident * type)) (l : list (ident * mval)) {struct l}
                            : list (ident * mval) :=
                            match ms, l with
                            | (_, t) :: ms', (g, v) :: l' => (g, clamp ce t v) :: go ms' l'
                            | _, _ => l
                            end) members fs in
              match (if bounded_name id then clamp_seq ce members fs' else None) with
              | Some mv' => mv'
              | None => MVstruct fs'
              end
          | None => mv
          end
      | _ => mv
      end
  | MVarray es =>
      match ty with
      | Tarray t _ => MVarray (map (clamp ce t) es)
      | _ => mv
      end
  end.

(** The fields of a struct, each converted by its member's type. *)
Definition clamp_fields (ce : composite_env) : list (ident * type) -> list (ident * mval) -> list (ident * mval) :=
  fix go (ms : list (ident * type)) (l : list (ident * mval)) {struct l} : list (ident * mval) :=
    match ms, l with
    | (_, t) :: ms', (g, v) :: l' => (g, clamp ce t v) :: go ms' l'
    | _, _ => l
    end.

Lemma clamp_struct_eq:
  forall ce id fs, clamp ce (Tstruct id) (MVstruct fs)
  = match struct_members ce id with
    | Some members =>
        match (if bounded_name id then clamp_seq ce members (clamp_fields ce members fs) else None) with
        | Some mv' => mv'
        | None => MVstruct (clamp_fields ce members fs)
        end
    | None => MVstruct fs
    end.
Proof. reflexivity. Qed.

Lemma elems_firstn:
  forall ce t es k, elems_have_type ce t es -> elems_have_type ce t (firstn k es).
Proof.
  intros ce t es k E. revert k. induction E as [|t0 e es' Te Es IH]; intros [|k]; simpl; constructor; auto.
Qed.

Lemma elems_app:
  forall ce t l1 l2, elems_have_type ce t l1 -> elems_have_type ce t l2 -> elems_have_type ce t (l1 ++ l2).
Proof. intros ce t l1 l2 E1 E2. induction E1; simpl; auto. constructor; auto. Qed.

(** The members of a struct of a well-formed environment have complete
    types. *)
Lemma struct_members_complete:
  forall ce id ms f t, wf_composites ce -> struct_members ce id = Some ms -> In (f, t) ms ->
  complete_type (composite_names ce) t = true.
Proof.
  intros ce id ms f t WF SM I. unfold struct_members in SM.
  destruct (find_composite id ce) as [c|] eqn:F; [|discriminate]. inversion SM; subst ms.
  destruct (find_composite_split _ _ _ F) as [_ [pre [post [E _]]]].
  destruct (composites_ok_inv ce [] WF) as [_ [_ C]].
  destruct (C pre c post E) as [_ T]. eapply complete_type_incl; [|apply (T f t I)].
  intros x Hx. rewrite app_nil_r in Hx. rewrite E. unfold composite_names. rewrite map_app. apply in_or_app. auto.
Qed.

Lemma clamp_seq_typed:
  forall ce id members fs mv', wf_composites ce ->
  struct_members ce id = Some members -> fields_have_type ce members fs ->
  clamp_seq ce members fs = Some mv' -> mval_has_type ce (Tstruct id) mv'.
Proof.
  intros ce id members fs mv' WF SM F C. unfold clamp_seq in C.
  destruct members as [|[x1 t1] [|[x2 t2] [|[x3 t3] [|]]]]; try discriminate;
  destruct fs as [|[f1 v1] [|[f2 v2] [|[f3 v3] [|]]]]; try discriminate;
  destruct t1 as [| [] [] | | | | | |]; try discriminate;
  destruct t2 as [| [] [] | | | | | |]; try discriminate;
  destruct t3 as [| | | | | t n | |]; try discriminate;
  destruct v1 as [[| len0 | | | | |]| |]; try discriminate;
  destruct v3 as [| |es]; try discriminate.
  inversion C; subst mv'; clear C.
  assert (Ct: complete_type (composite_names ce) t = true).
  { assert (Ca := struct_members_complete ce id _ x3 (Tarray t n) WF SM ltac:(simpl; auto)).
    simpl in Ca. apply andb_true_iff in Ca; tauto. }
  inversion F as [|? ? ? ? ? T1 F2]; subst. inversion F2 as [|? ? ? ? ? T2 F3]; subst.
  inversion F3 as [|? ? ? ? ? T3 F4]; subst.
  inversion T1 as [? ? _ V1| |]; subst. inversion T3 as [| |? ? ? L3 E3]; subst.
  simpl in V1. unfold norm_int, wrap, wrap_unsigned, bitsize in V1. simpl in V1.
  assert (Hl: (0 <= len0 < 4294967296)%Z) by (rewrite <- V1; apply Z.mod_pos_bound; lia).
  assert (Lk: (Z.to_nat (Z.min len0 (Z.of_nat (length es))) <= length es)%nat) by lia.
  econstructor; [exact SM|]. constructor; [|constructor; [|constructor; [|constructor]]].
  - constructor; [reflexivity|]. simpl. unfold norm_int, wrap, wrap_unsigned, bitsize. simpl.
    apply Z.mod_small. lia.
  - constructor; [reflexivity|]. simpl. destruct (_ <? len0)%Z; reflexivity.
  - constructor.
    + rewrite app_length, firstn_length, repeat_length. lia.
    + apply elems_app; [apply elems_firstn; auto|].
      generalize (length es - Z.to_nat (Z.min len0 (Z.of_nat (length es))))%nat.
      intros k; induction k; simpl; constructor; auto. apply zero_mval_has_type; auto.
Qed.

Lemma clamp_fields_typed:
  forall ce members fs,
  Forall (fun fv => forall ty, mval_has_type ce ty (snd fv) -> mval_has_type ce ty (clamp ce ty (snd fv))) fs ->
  fields_have_type ce members fs ->
  fields_have_type ce members
    ((fix go (ms : list (ident * type)) (l : list (ident * mval)) {struct l} : list (ident * mval) :=
        match ms, l with
        | (_, t) :: ms', (g, v) :: l' => (g, clamp ce t v) :: go ms' l'
        | _, _ => l
        end) members fs).
Proof.
  intros ce members fs IH. revert members. induction IH as [|[g v] fs Hv Hfs IHfs]; intros members F.
  - inversion F; subst. constructor.
  - inversion F as [|f t mv' members' fs' Tv F']; subst. simpl. constructor; auto.
Qed.

Lemma clamp_typed:
  forall ce mv ty, wf_composites ce -> mval_has_type ce ty mv -> mval_has_type ce ty (clamp ce ty mv).
Proof.
  intros ce mv ty WF. revert ty. induction mv as [v|fs IH|es IH] using mval_ind2; intros ty T.
  - simpl. exact T.
  - inversion T as [|id members fs' SM F|]; subst. simpl. rewrite SM.
    assert (F' := clamp_fields_typed ce members fs IH F).
    match goal with |- context [if bounded_name id then clamp_seq ce members ?x else None] =>
      destruct (if bounded_name id then clamp_seq ce members x else None) as [mv'|] eqn:C end.
    + destruct (bounded_name id); [|discriminate]. eapply clamp_seq_typed; eauto.
    + econstructor; eauto.
  - inversion T as [| |t n es' L E]; subst. simpl. constructor.
    + rewrite map_length. reflexivity.
    + clear T. induction IH as [|e es He Hes IHes]; simpl; inversion E; subst; constructor; auto.
Qed.

Lemma nth_error_firstn_lt:
  forall (A : Type) (l : list A) k i, (i < k)%nat -> nth_error (firstn k l) i = nth_error l i.
Proof.
  intros A l; induction l as [|x l IH]; intros [|k] [|i] H; simpl; auto; try lia.
  apply IH. lia.
Qed.

(** Converting scalars changes nothing. *)
Lemma map_clamp_scalar:
  forall ce t es, is_scalar_type t = true -> elems_have_type ce t es -> map (clamp ce t) es = es.
Proof.
  intros ce t es St E. induction E as [|t0 e es' Te Es IH]; simpl; auto. f_equal; auto.
  inversion Te; subst; simpl in St; try discriminate; reflexivity.
Qed.

(** The same for a sequence of any element type (structs, which may hold
    sequences themselves, included): each of its first [min(len, n)]
    elements converted, then zeros of the element's type. *)
Lemma clamp_bounded_elems:
  forall ce id mv l n t,
  bounded_name id = true ->
  struct_members ce id = Some [("len"%string, Tint I32 Unsigned); ("truncated"%string, Tint I8 Unsigned); ("data"%string, Tarray t n)] ->
  mval_has_type ce (Tstruct id) mv ->
  mval_get mv [Sfield "len"%string] = Some (MVscalar (Vint l)) ->
  let cv := clamp ce (Tstruct id) mv in
     mval_get cv [Sfield "len"%string] = Some (MVscalar (Vint (Z.min l n)))
  /\ mval_get cv [Sfield "truncated"%string] = Some (MVscalar (Vint (if (n <? l)%Z then 1 else 0)))
  /\ (forall i, (0 <= i < n)%Z ->
        mval_get cv [Sfield "data"%string; Sindex i]
        = if (i <? Z.min l n)%Z then option_map (clamp ce t) (mval_get mv [Sfield "data"%string; Sindex i])
          else Some (zero_mval ce t)).
Proof.
  intros ce id mv l n t B SM T Gl cv.
  inversion T as [? ? Hs|? members fs SM0 F|]; subst; [discriminate Hs|].
  rewrite SM in SM0. inversion SM0; subst members. clear SM0.
  inversion F as [|f1 t1 v1 ms1 fs1 T1 F1]; subst.
  inversion F1 as [|f2 t2 v2 ms2 fs2 T2 F2]; subst.
  inversion F2 as [|f3 t3 v3 ms3 fs3 T3 F3]; subst.
  inversion F3; subst.
  inversion T3 as [? ? Hs3| |t' n' es L E]; subst; [discriminate Hs3|].
  simpl in Gl. inversion Gl; subst v1.
  unfold cv; simpl. rewrite SM, B. simpl.
  split; [reflexivity|split; [reflexivity|]].
  intros i Hi. destruct (Z.leb_spec 0 i) as [_|N]; [|lia].
  inversion T1 as [? ? _ V1| |]; subst.
  simpl in V1. unfold norm_int, wrap, wrap_unsigned, bitsize in V1. simpl in V1.
  assert (Hl: (0 <= l)%Z) by (rewrite <- V1; apply Z.mod_pos_bound; lia).
  set (k := Z.min l (Z.of_nat (length es))).
  assert (Hk: (0 <= k <= Z.of_nat (length es))%Z) by (unfold k; lia).
  rewrite map_length. fold k.
  destruct (Z.ltb_spec i k) as [Lt|Ge].
  - rewrite nth_error_app1 by (rewrite firstn_length, map_length; lia).
    rewrite nth_error_firstn_lt by lia. rewrite nth_error_map.
    destruct (nth_error es (Z.to_nat i)); reflexivity.
  - rewrite nth_error_app2 by (rewrite firstn_length, map_length; lia).
    rewrite nth_error_repeat; [reflexivity|]. rewrite firstn_length, map_length. lia.
Qed.

(** What the callback receives of a bounded sequence of scalars: its
    length capped at [n], whether it was longer than [n], and its first
    [min(len, n)] elements followed by zeros. *)
Lemma clamp_bounded:
  forall ce id mv l n t,
  bounded_name id = true ->
  struct_members ce id = Some [("len"%string, Tint I32 Unsigned); ("truncated"%string, Tint I8 Unsigned); ("data"%string, Tarray t n)] ->
  is_scalar_type t = true ->
  mval_has_type ce (Tstruct id) mv ->
  mval_get mv [Sfield "len"%string] = Some (MVscalar (Vint l)) ->
  let cv := clamp ce (Tstruct id) mv in
     mval_get cv [Sfield "len"%string] = Some (MVscalar (Vint (Z.min l n)))
  /\ mval_get cv [Sfield "truncated"%string] = Some (MVscalar (Vint (if (n <? l)%Z then 1 else 0)))
  /\ (forall i, (0 <= i < n)%Z ->
        mval_get cv [Sfield "data"%string; Sindex i]
        = if (i <? Z.min l n)%Z then mval_get mv [Sfield "data"%string; Sindex i]
          else Some (MVscalar (zero_val t))).
Proof.
  intros ce id mv l n t B SM St T Gl cv. subst cv.
  destruct (clamp_bounded_elems ce id mv l n t B SM T Gl) as (L & Tr & D).
  split; [exact L|split; [exact Tr|]]. intros i Hi. rewrite (D i Hi).
  destruct (i <? Z.min l n)%Z.
  - (* a scalar element is its own conversion *)
    destruct (mval_get_has_type ce [Sfield "data"%string; Sindex i] (Tstruct id) mv t T) as (v & G & Tv).
    + simpl. rewrite SM. simpl. destruct (Z.leb 0 i && Z.ltb i n) eqn:R; [reflexivity|].
      apply andb_false_iff in R. destruct R as [R|R]; [apply Z.leb_gt in R|apply Z.ltb_ge in R]; lia.
    + rewrite G. inversion Tv; subst; simpl in St; try discriminate; reflexivity.
  - unfold zero_mval. rewrite (default_mval_scalar _ ce t St). reflexivity.
Qed.

(** [p] leads from a value of type [ty] through no bounded sequence
    (the last step may reach one). *)
Fixpoint unbounded_path (ce : composite_env) (ty : type) (p : path) : bool :=
  match p with
  | [] => true
  | s :: p' =>
      match ty with Tstruct id => negb (bounded_name id) | _ => true end
      && match type_step ce ty s with Some t => unbounded_path ce t p' | None => false end
  end.

Lemma clamp_fields_find:
  forall ce members fs f v t,
  fields_have_type ce members fs -> find_assoc f fs = Some v -> field_type f members = Some t ->
  find_assoc f ((fix go (ms : list (ident * type)) (l : list (ident * mval)) {struct l}
                   : list (ident * mval) :=
                   match ms, l with
                   | (_, t) :: ms', (g, v) :: l' => (g, clamp ce t v) :: go ms' l'
                   | _, _ => l
                   end) members fs) = Some (clamp ce t v).
Proof.
  intros ce members fs f v t F. revert v t. induction F as [|g tg mv members fs Tg F IH]; intros v t Hf Ht.
  - discriminate.
  - simpl in Hf, Ht |- *. unfold field_type in Ht. simpl in Ht.
    destruct (string_dec f g) as [->|N].
    + inversion Hf; inversion Ht; subst. reflexivity.
    + apply IH; auto.
Qed.

(** Converting a message and then following a path through no bounded
    sequence is following the path and then converting. *)
Lemma clamp_get:
  forall ce p ty mv t v,
  mval_has_type ce ty mv -> unbounded_path ce ty p = true ->
  type_at ce ty p = Some t -> mval_get mv p = Some v ->
  mval_get (clamp ce ty mv) p = Some (clamp ce t v).
Proof.
  intros ce p; induction p as [|s p IH]; intros ty mv t v T U Ty G.
  - simpl in Ty, G. inversion Ty; inversion G; subst. reflexivity.
  - simpl in U, Ty, G. apply andb_true_iff in U. destruct U as [Nb U].
    destruct (type_step ce ty s) as [ts|] eqn:Ts; [|discriminate].
    destruct (get_step mv s) as [x|] eqn:Gs; [|discriminate].
    destruct s as [f|i]; destruct ty as [| | | |t0 | t0 n | | id]; try discriminate.
    + (* a field *)
      simpl in Ts. destruct (struct_members ce id) as [members|] eqn:SM; [|discriminate].
      inversion T as [? ? Hs|? members' fs SM' F|]; subst; [discriminate Hs|].
      rewrite SM in SM'. inversion SM'; subst members'. clear SM'.
      apply negb_true_iff in Nb. simpl. rewrite SM, Nb.
      simpl in Gs. simpl. rewrite (clamp_fields_find ce members fs f x ts F Gs Ts).
      apply IH; auto.
      clear IH G T SM. revert x Ts Gs. induction F as [|g tg mv members fs Tg F IHF]; intros x Ts Gx.
      * discriminate.
      * simpl in Gx. unfold field_type in Ts. simpl in Ts.
        destruct (string_dec f g) as [->|N]; [inversion Gx; inversion Ts; subst; auto|].
        eapply IHF; eauto.
    + (* an element *)
      simpl in Ts. destruct (Z.leb 0 i && Z.ltb i n) eqn:B; [|discriminate]. inversion Ts; subst ts.
      inversion T as [? ? Hs| |t' n' es L E]; subst; [discriminate Hs|].
      simpl in Gs |- *. destruct (Z.leb 0 i); [|discriminate].
      rewrite nth_error_map, Gs. simpl. apply IH; auto.
      clear IH G T B Ts. revert Gs. generalize (Z.to_nat i). induction E as [|t1 e es' Te Es IHE]; intros [|k] Gk;
        simpl in Gk; try discriminate; [inversion Gk; subst; auto|eapply IHE; eauto].
Qed.

(** Policy "reject" (issue 15): whether the message [mv] of type [ty]
    holds a bounded sequence whose struct is named [ros_rseq_...] or
    [ros_rstring...] ([reject_name]) and whose length exceeds its
    capacity [n]: such a message is not delivered ([accepted]). *)
Definition seq_too_long (members : list (ident * type)) (fs : list (ident * mval)) : bool :=
  match members, fs with
  | [_; _; (_, Tarray _ n)], (_, MVscalar (Vint l)) :: _ => (n <? l)%Z
  | _, _ => false
  end.

Fixpoint too_long (ce : composite_env) (ty : type) (mv : mval) {struct mv} : bool :=
  match mv with
  | MVscalar _ => false
  | MVstruct fs =>
      match ty with
      | Tstruct id =>
          match struct_members ce id with
          | Some members =>
              (reject_name id && seq_too_long members fs)
              || (fix go (ms : list (ident * type)) (l : list (ident * mval)) {struct l} : bool :=
                    match ms, l with
                    | (_, t) :: ms', (_, v) :: l' => too_long ce t v || go ms' l'
                    | _, _ => false
                    end) members fs
          | None => false
          end
      | _ => false
      end
  | MVarray es =>
      match ty with
      | Tarray t _ => existsb (too_long ce t) es
      | _ => false
      end
  end.

(** Whether subscription [s] delivers the arrival [a] to its callback:
    unless a sequence with policy "reject" is longer than its maximum,
    in which case the message is dropped after the queue (the callback
    is not called; the topic's global and clock keep the previous
    message's). *)
Definition accepted (ge : genv) (s : subscription) (a : arrival) : bool :=
  negb (too_long (ge_comp ge) (Tstruct (sub_msgty s)) (ar_msg a)).

(** The value that the callback of subscription [s] receives for the
    arrival [a]: the message with its bounded sequences converted. *)
Definition delivered (ge : genv) (s : subscription) (a : arrival) : mval :=
  clamp (ge_comp ge) (Tstruct (sub_msgty s)) (ar_msg a).

(** The two targets (rule 4.17): the node runs on ROS 1 (roscpp, the
    wrapper [<node>_ros.cpp]) or on ROS 2 (rcl, the wrapper
    [<node>_rcl.c]).  They differ only in what one [ros_spinOnce]
    delivers ([spin_messages]: [deliverable] for ROS 1, [rcl_deliverable]
    for ROS 2). *)
Inductive target : Type := Ros1 | Ros2.

Definition target_eq_dec (a b : target) : {a = b} + {a <> b}.
Proof. decide equality. Defined.

(** What the environment of a run fixes: the message arrivals with their
    receipt times, the ROS time of each cycle, the controller and the
    target the node runs on. *)
Record ros_context (CS : Type) : Type := mkctx {
  ctx_arrivals : nat -> list arrival;
  ctx_time : nat -> Z;
  ctx_init : CS;
  ctx_step : CS -> mval -> CS * mval;
  ctx_target : target
}.

Arguments mkctx {CS} ctx_arrivals ctx_time ctx_init ctx_step ctx_target.
Arguments ctx_arrivals {CS} r _.
Arguments ctx_time {CS} r _.
Arguments ctx_init {CS} r.
Arguments ctx_step {CS} r _ _.
Arguments ctx_target {CS} r.

(** The state of the world outside the program's memory. *)
Record world (CS : Type) : Type := mkworld {
  w_subs : list subscription;   (**r subscriptions, in registration order *)
  w_advertised : list string;   (**r advertised topics *)
  w_spins : nat;                (**r calls of [ros_spinOnce] so far *)
  w_ok : nat;                   (**r remaining [true] answers of [ros_ok] *)
  w_ctrl : option CS;           (**r the controller's state; [None]: not initialised *)
  w_time : Z                    (**r what [ros_now] answers *)
}.

Arguments mkworld {CS} w_subs w_advertised w_spins w_ok w_ctrl w_time.
Arguments w_subs {CS} w.
Arguments w_advertised {CS} w.
Arguments w_spins {CS} w.
Arguments w_ok {CS} w.
Arguments w_ctrl {CS} w.
Arguments w_time {CS} w.

(** The world at the start of [main]: the time is the one read by
    [ros_init], [ctx_time ctx 0]. *)
Definition initial_world {CS : Type} (ctx : ros_context CS) (n : nat) : world CS :=
  mkworld [] [] O n None (ctx_time ctx O).

Definition add_subscription {CS} (w : world CS) (s : subscription) : world CS :=
  mkworld (w_subs w ++ [s]) (w_advertised w) (w_spins w) (w_ok w) (w_ctrl w) (w_time w).
Definition add_advertised {CS} (w : world CS) (topic : string) : world CS :=
  mkworld (w_subs w) (w_advertised w ++ [topic]) (w_spins w) (w_ok w) (w_ctrl w) (w_time w).
Definition set_ok {CS} (w : world CS) (k : nat) : world CS :=
  mkworld (w_subs w) (w_advertised w) (w_spins w) k (w_ctrl w) (w_time w).
Definition set_ctrl {CS} (w : world CS) (s : option CS) : world CS :=
  mkworld (w_subs w) (w_advertised w) (w_spins w) (w_ok w) s (w_time w).
Definition set_time {CS} (w : world CS) (t : Z) : world CS :=
  mkworld (w_subs w) (w_advertised w) (w_spins w) (w_ok w) (w_ctrl w) t.

(** The end of a [ros_spinOnce]: one more spin, and the time is the
    cycle's, read when [ros::spinOnce] returned. *)
Definition next_spin {CS} (ctx : ros_context CS) (w : world CS) : world CS :=
  mkworld (w_subs w) (w_advertised w) (S (w_spins w)) (w_ok w) (w_ctrl w)
          (ctx_time ctx (S (w_spins w))).

Definition topic_eqb (a b : string) : bool := if string_dec a b then true else false.

(** The number of messages on [topic] in [msgs]. *)
Fixpoint count_topic (topic : string) (msgs : list arrival) : nat :=
  match msgs with
  | [] => O
  | a :: rest => (if topic_eqb (ar_topic a) topic then 1 else 0) + count_topic topic rest
  end%nat.

(** Whether subscription [s] still holds a message after which [newer]
    messages arrived on its topic: its queue keeps the newest
    [sub_queue s] messages, all of them when the queue size is 0. *)
Definition keeps (s : subscription) (newer : nat) : bool :=
  Nat.eqb (sub_queue s) 0 || Nat.ltb newer (sub_queue s).

(** The callback invocations performed by one [ros_spinOnce] when the
    messages [msgs] arrived since the previous one: for each message in
    arrival order, one invocation per subscription of its topic whose
    queue still holds it (subscriptions in registration order).  Messages
    of topics without subscription are dropped. *)
Fixpoint deliverable (subs : list subscription) (msgs : list arrival)
  : list (subscription * arrival) :=
  match msgs with
  | [] => []
  | a :: rest =>
      map (fun s => (s, a))
          (filter (fun s => topic_eqb (sub_topic s) (ar_topic a)
                            && keeps s (count_topic (ar_topic a) rest)) subs)
      ++ deliverable subs rest
  end.

(** *** ROS 2 *)

(** What one [ros_spinOnce] of the ROS 2 wrapper ([rcl_api.c.j2]) delivers
    when the messages [msgs] arrived since the previous one.  Each
    subscription's reader has a history KEEP_LAST of depth [sub_queue s]:
    of the arrivals on its topic it holds the newest [sub_queue s]
    ([history]; depth 0 holds none, as the wrapper then takes none: the
    generator refuses a queue size of 0 for both targets, rule 4.4 and
    [Wellformed]).  The wrapper takes them with [rcl_take], oldest first
    ([taken]), from each subscription in registration order, and runs the
    callback of each message as it is taken: [rcl_deliverable] is the
    concatenation of the subscriptions' lists, as rclcpp's executor runs
    the ready subscriptions one after the other, not interleaved on a
    time.  (Callbacks of different topics write disjoint globals, so no
    glue can tell the order of messages of different topics; T2's proof
    uses only that a spin delivers registered topics' arrivals and that
    the last accepted delivery to a subscription is its newest kept
    message, [Loopfacts.In_spin_messages] and
    [Loopfacts.last_delivered_rcl_deliverable].)  A message of policy
    "reject" that is too long is taken like any other and dropped when
    its turn comes ([Semantics.deliver_rejected]; the wrapper skips its
    callback).  Messages of topics nobody subscribed to are dropped. *)
Fixpoint history (topic : string) (q : nat) (msgs : list arrival) : list arrival :=
  match msgs with
  | [] => []
  | a :: rest =>
      (if topic_eqb (ar_topic a) topic && Nat.ltb (count_topic topic rest) q then [a] else [])
      ++ history topic q rest
  end.

Definition taken (s : subscription) (msgs : list arrival) : list (subscription * arrival) :=
  map (fun a => (s, a)) (history (sub_topic s) (sub_queue s) msgs).

Definition rcl_deliverable (subs : list subscription) (msgs : list arrival) : list (subscription * arrival) :=
  flat_map (fun s => taken s msgs) subs.

(** ** The external functions *)

(** The two fields of a ROS time given in nanoseconds (as [ros::Time]
    holds it: [sec] and [nsec], both [uint32]): for every ROS time
    ([0 <= t < 2^32 * 10^9]) exactly its [sec] and [nsec]; beyond, the
    time is first read modulo [2^64], as [ros_now] returns it, and the
    seconds modulo [2^32], as the [uint32] field holds them. *)
Definition time_sec (t : Z) : Z := norm_int I32 Unsigned (norm_long Unsigned t / 1000000000).
Definition time_nsec (t : Z) : Z := norm_int I32 Unsigned (norm_long Unsigned t mod 1000000000).

Section EXTERNAL.

Context {CS : Type}.
Variable ctx : ros_context CS.
Variable ge : genv.

(** The external functions other than [ros_spinOnce] (see the header):
    result, events, new memory and new world, or [None] when the call is
    undefined. *)
Definition external_call (ef : external_function) (vargs : list val) (m : mem) (w : world CS)
  : option (val * trace * mem * world CS) :=
  match ef, vargs with
  | EF_ros_init, [] => Some (Vundef, [], m, w)
  | EF_ros_ok, [] =>
      match w_ok w with
      | S k => Some (Vint 1, [], m, set_ok w k)
      | O => Some (Vint 0, [], m, w)
      end
  | EF_ros_now, [] => Some (Vlong (norm_long Unsigned (w_time w)), [], m, w)
  | EF_ros_time_sec, [] => Some (Vint (time_sec (w_time w)), [], m, w)
  | EF_ros_time_nsec, [] => Some (Vint (time_nsec (w_time w)), [], m, w)
  | EF_ros_rate_sleep period, [] => Some (Vundef, [Esleep period], m, w)
  | EF_ros_subscribe topic msgty q, [Vfptr cb] =>
      Some (Vundef, [Esubscribe topic msgty q], m, add_subscription w (mksub topic msgty q cb))
  | EF_ros_advertise topic msgty q, [] =>
      Some (Vundef, [Eadvertise topic msgty q], m, add_advertised w topic)
  | EF_ros_publish topic msgty, [Vptr b p] =>
      if existsb (topic_eqb topic) (w_advertised w) then
        match load_path m b p with
        | Some mv => Some (Vundef, [Epublish topic (clamp (ge_comp ge) (Tstruct msgty) mv)], m, w)
        | None => None
        end
      else None
  | EF_controller_initialize _ _, [] => Some (Vundef, [Einit], m, set_ctrl w (Some (ctx_init ctx)))
  | EF_controller_step u y, [] =>
      match w_ctrl w, find_var ge u, find_var ge y with
      | Some s, Some (bu, tu), Some (by_, ty) =>
          match load_path m bu [], load_path m by_ [] with
          | Some uv, Some yv0 =>
              if mval_typecheck (ge_comp ge) tu uv && mval_typecheck (ge_comp ge) ty yv0 then
                let (s', yv) := ctx_step ctx s uv in
                if mval_typecheck (ge_comp ge) ty yv then
                  match store_path m by_ [] yv with
                  | Some m' => Some (Vundef, [Estep uv yv], m', set_ctrl w (Some s'))
                  | None => None
                  end
                else None
              else None
          | _, _ => None
          end
      | _, _, _ => None
      end
  | _, _ => None
  end.

(** The messages one [ros_spinOnce] delivers, as the target's wrapper
    does. *)
Definition spin_messages (w : world CS) : list (subscription * arrival) :=
  match ctx_target ctx with
  | Ros1 => deliverable (w_subs w) (ctx_arrivals ctx (w_spins w))
  | Ros2 => rcl_deliverable (w_subs w) (ctx_arrivals ctx (w_spins w))
  end.

Lemma external_call_not_spin:
  forall vargs m w r, external_call EF_ros_spinOnce vargs m w = Some r -> False.
Proof. intros vargs m w r H; destruct vargs; discriminate. Qed.

End EXTERNAL.
