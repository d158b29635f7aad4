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
      state and the new value of the outputs global ([Controller_Y]).
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
      counter) and computes [deliverable subs msgs]: for each
      subscription, the messages of its topic, of which a queue of size
      [q] keeps the newest [q] ([q = 0]: unbounded, as in roscpp);
      messages of topics nobody subscribed to are dropped; arrival order
      is kept.  Then, for each kept message in order, a fresh block
      holding the message value (of type [struct msgty]) is allocated,
      the callback is called with a pointer to it, and the block is freed
      ([deliver]).  Finally the spin counter is incremented.  It emits
      nothing itself (the callbacks may).
    - [ros_publish_T(&msg)] ([EF_ros_publish topic msgty]), with argument a
      pointer: the topic must have been advertised; the value at the
      pointer is emitted as the event [Epublish topic value].
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

From Coq Require Import String List ZArith Bool.
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

(** What the environment of a run fixes: the message arrivals with their
    receipt times, the ROS time of each cycle and the controller. *)
Record ros_context (CS : Type) : Type := mkctx {
  ctx_arrivals : nat -> list arrival;
  ctx_time : nat -> Z;
  ctx_init : CS;
  ctx_step : CS -> mval -> CS * mval
}.

Arguments mkctx {CS} ctx_arrivals ctx_time ctx_init ctx_step.
Arguments ctx_arrivals {CS} r _.
Arguments ctx_time {CS} r _.
Arguments ctx_init {CS} r.
Arguments ctx_step {CS} r _ _.

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
  | EF_ros_publish topic _, [Vptr b p] =>
      if existsb (topic_eqb topic) (w_advertised w) then
        match load_path m b p with
        | Some mv => Some (Vundef, [Epublish topic mv], m, w)
        | None => None
        end
      else None
  | EF_controller_initialize _ _, [] => Some (Vundef, [Einit], m, set_ctrl w (Some (ctx_init ctx)))
  | EF_controller_step u y, [] =>
      match w_ctrl w, find_var ge u, find_var ge y with
      | Some s, Some (bu, _), Some (by_, ty) =>
          match load_path m bu [] with
          | Some uv =>
              let (s', yv) := ctx_step ctx s uv in
              if mval_typecheck (ge_comp ge) ty yv then
                match store_path m by_ [] yv with
                | Some m' => Some (Vundef, [Estep uv yv], m', set_ctrl w (Some s'))
                | None => None
                end
              else None
          | None => None
          end
      | _, _, _ => None
      end
  | _, _ => None
  end.

(** The messages one [ros_spinOnce] delivers. *)
Definition spin_messages (w : world CS) : list (subscription * arrival) :=
  deliverable (w_subs w) (ctx_arrivals ctx (w_spins w)).

Lemma external_call_not_spin:
  forall vargs m w r, external_call EF_ros_spinOnce vargs m w = Some r -> False.
Proof. intros vargs m w r H; destruct vargs; discriminate. Qed.

End EXTERNAL.
