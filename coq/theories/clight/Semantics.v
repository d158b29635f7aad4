(** * Big-step semantics of the Clight subset, with the ROS environment model *)

(** This file gives the meaning of the programs of [Syntax]:
    - expressions are evaluated by *functions* ([eval_expr],
      [eval_lvalue]): expressions of the subset have no side effects, so
      their evaluation is deterministic; the relational reading is
      [eval_expr ... a = Some v];
    - statements, function calls and the delivery of messages by
      [ros_spinOnce] are big-step judgements ([exec_stmt], [eval_funcall],
      [deliver]), mutually inductive because [ros_spinOnce] runs the
      callbacks, which are functions of the program;
    - external functions (the ROS C API and the controller interface) get
      their meaning from the environment model below;
    - [program_behaves p ctx n t]: [main] runs to completion with trace [t]
      when [ros_ok] answers true [n] times.

    ** The ROS environment model

    A [ros_context CS] fixes everything the program cannot control:
    - [ctx_arrivals k]: the messages [(topic, value)] that arrive, in
      order, between the [k-1]-th and the [k]-th call of [ros_spinOnce]
      (calls counted from 0);
    - a controller: a state type [CS], an initial state [ctx_init] and a
      step function [ctx_step : CS -> mval -> CS * mval] that receives the
      whole value of the inputs global ([Controller_U]) and returns its new
      state and the new value of the outputs global ([Controller_Y]).
    The number [n] of [true] answers of [ros_ok] is a parameter of
    [program_behaves].

    The [world] is the part of the state that lives outside the program's
    memory: the subscriptions registered so far (topic, message struct,
    queue size, callback), the advertised topics, the number of spins so
    far, the remaining [true] answers of [ros_ok], and the controller's
    state.  The external functions act as follows:
    - [ros_init()]: nothing.
    - [ros_ok()]: returns 1 and consumes one [true] answer if one is left,
      otherwise returns 0.
    - [ros_subscribe_T(cb)] ([EF_ros_subscribe topic msgty q]), with
      argument the function pointer [Vfptr cb]: registers the subscription
      [(topic, msgty, q, cb)].
    - [ros_advertise_T()]: registers the topic as advertised.
    - [ros_spinOnce()]: takes the messages [ctx_arrivals k] ([k] the spin
      counter) and computes [deliverable subs msgs]: for each
      subscription, the messages of its topic, of which a queue of size
      [q] keeps the newest [q] ([q = 0]: unbounded, as in roscpp);
      messages of topics nobody subscribed to are dropped; arrival order
      is kept.  Then, for each kept message in order, a fresh block
      holding the message value (of type [struct msgty]) is allocated,
      the callback is called with a pointer to it, and the block is freed
      ([deliver]).  Finally the spin counter is incremented.
    - [ros_publish_T(&msg)] ([EF_ros_publish topic msgty]), with argument a
      pointer: the topic must have been advertised; the value at the
      pointer is emitted as the event [Epublish topic value].
    - [ros_rate_sleep()]: emits [Ecycle], which marks the end of a cycle.
    - [Controller_initialize()] ([EF_controller_initialize u y]): sets the
      controller state to [ctx_init].
    - [Controller_step()] ([EF_controller_step u y]): reads the whole value
      [uv] of the global [u], computes [(s', yv) := ctx_step s uv], stores
      [yv] into the global [y] and emits [Estep uv yv].  If [yv] does not
      have the type of [y], the step is undefined (the semantics is
      stuck): the controller may only write its outputs, at their type.

    The trace of a run is the list of its events in the order they
    happen. *)

From Coq Require Import String List ZArith Bool Lia.
From ROSGen Require Import Syntax Values Memory.
Import ListNotations.
Local Open Scope Z_scope.

(** ** Events and traces *)

Inductive event : Type :=
  | Estep (u y : mval)                 (**r [Controller_step] read [u] and wrote [y] *)
  | Epublish (topic : string) (m : mval)  (**r message [m] published on [topic] *)
  | Ecycle.                            (**r [ros_rate_sleep]: end of a cycle *)

Definition trace := list event.

(** ** Association lists *)

(** Update or add the binding of [x]. *)
Fixpoint set_assoc {A : Type} (x : ident) (v : A) (l : list (ident * A)) : list (ident * A) :=
  match l with
  | [] => [(x, v)]
  | (y, w) :: l' => if ident_eq x y then (y, v) :: l' else (y, w) :: set_assoc x v l'
  end.

Lemma find_assoc_set_same:
  forall A x (v : A) l, find_assoc x (set_assoc x v l) = Some v.
Proof.
  induction l as [|[y w] l IH]; simpl.
  - destruct (string_dec x x); congruence.
  - destruct (ident_eq x y) as [E|N]; simpl.
    + subst; destruct (string_dec y y); congruence.
    + destruct (string_dec x y); [congruence | auto].
Qed.

Lemma find_assoc_set_other:
  forall A x y (v : A) l, y <> x -> find_assoc y (set_assoc x v l) = find_assoc y l.
Proof.
  induction l as [|[z w] l IH]; simpl; intros N.
  - destruct (string_dec y x); congruence.
  - destruct (ident_eq x z) as [E|E]; simpl.
    + subst z. destruct (string_dec y x); congruence.
    + destruct (string_dec y z); auto.
Qed.

(** ** Environments *)

(** The global environment: struct definitions, the block and type of
    each global variable, the definition of each function. *)
Record genv : Type := mkgenv {
  ge_comp : composite_env;
  ge_vars : list (ident * (block * type));
  ge_funs : list (ident * fundef)
}.

Definition find_var (ge : genv) (x : ident) : option (block * type) := find_assoc x (ge_vars ge).
Definition find_funct (ge : genv) (x : ident) : option fundef := find_assoc x (ge_funs ge).

(** Local environment: block and type of each addressable local. *)
Definition env := list (ident * (block * type)).

(** Temporaries (parameters included): their current values. *)
Definition temp_env := list (ident * val).

(** ** The ROS environment model *)

(** A subscription, as registered by [ros_subscribe_T]. *)
Record subscription : Type := mksub {
  sub_topic : string;      (**r the topic *)
  sub_msgty : ident;       (**r the message struct *)
  sub_queue : nat;         (**r the queue size (0: unbounded) *)
  sub_callback : ident     (**r the callback function *)
}.

(** What the environment of a run fixes: the message arrivals and the
    controller. *)
Record ros_context (CS : Type) : Type := mkctx {
  ctx_arrivals : nat -> list (string * mval);
  ctx_init : CS;
  ctx_step : CS -> mval -> CS * mval
}.

Arguments mkctx {CS} ctx_arrivals ctx_init ctx_step.
Arguments ctx_arrivals {CS} r _.
Arguments ctx_init {CS} r.
Arguments ctx_step {CS} r _ _.

(** The state of the world outside the program's memory. *)
Record world (CS : Type) : Type := mkworld {
  w_subs : list subscription;   (**r subscriptions, in registration order *)
  w_advertised : list string;   (**r advertised topics *)
  w_spins : nat;                (**r calls of [ros_spinOnce] so far *)
  w_ok : nat;                   (**r remaining [true] answers of [ros_ok] *)
  w_ctrl : CS                   (**r the controller's state *)
}.

Arguments mkworld {CS} w_subs w_advertised w_spins w_ok w_ctrl.
Arguments w_subs {CS} w.
Arguments w_advertised {CS} w.
Arguments w_spins {CS} w.
Arguments w_ok {CS} w.
Arguments w_ctrl {CS} w.

(** The world at the start of [main]. *)
Definition initial_world {CS : Type} (ctx : ros_context CS) (n : nat) : world CS :=
  mkworld [] [] O n (ctx_init ctx).

Definition add_subscription {CS} (w : world CS) (s : subscription) : world CS :=
  mkworld (w_subs w ++ [s]) (w_advertised w) (w_spins w) (w_ok w) (w_ctrl w).
Definition add_advertised {CS} (w : world CS) (topic : string) : world CS :=
  mkworld (w_subs w) (w_advertised w ++ [topic]) (w_spins w) (w_ok w) (w_ctrl w).
Definition set_ok {CS} (w : world CS) (k : nat) : world CS :=
  mkworld (w_subs w) (w_advertised w) (w_spins w) k (w_ctrl w).
Definition next_spin {CS} (w : world CS) : world CS :=
  mkworld (w_subs w) (w_advertised w) (S (w_spins w)) (w_ok w) (w_ctrl w).
Definition set_ctrl {CS} (w : world CS) (s : CS) : world CS :=
  mkworld (w_subs w) (w_advertised w) (w_spins w) (w_ok w) s.

Definition topic_eqb (a b : string) : bool := if string_dec a b then true else false.

(** The number of messages on [topic] in [msgs]. *)
Fixpoint count_topic (topic : string) (msgs : list (string * mval)) : nat :=
  match msgs with
  | [] => O
  | (tp, _) :: rest => (if topic_eqb tp topic then 1 else 0) + count_topic topic rest
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
Fixpoint deliverable (subs : list subscription) (msgs : list (string * mval))
  : list (subscription * mval) :=
  match msgs with
  | [] => []
  | (tp, mv) :: rest =>
      map (fun s => (s, mv))
          (filter (fun s => topic_eqb (sub_topic s) tp && keeps s (count_topic tp rest)) subs)
      ++ deliverable subs rest
  end.

(** ** Evaluation of expressions *)

Section EXPR.

Variable ge : genv.
Variable e : env.
Variable le : temp_env.
Variable m : mem.

(** The location of variable [x]: a local first, then a global. *)
Definition lvalue_var (x : ident) : option (block * path) :=
  match find_assoc x e with
  | Some (b, _) => Some (b, [])
  | None =>
      match find_var ge x with
      | Some (b, _) => Some (b, [])
      | None => None
      end
  end.

(** [x] as a function designator: a function that no variable hides. *)
Definition eval_funcname (x : ident) : option val :=
  match find_assoc x e, find_var ge x, find_funct ge x with
  | None, None, Some _ => Some (Vfptr x)
  | _, _, _ => None
  end.

(** The location designated by [*a], given the value of [a]. *)
Definition lvalue_deref (v : option val) : option (block * path) :=
  match v with
  | Some (Vptr b p) => Some (b, p)
  | _ => None
  end.

(** The location of [a.f], given the location of [a]. *)
Definition lvalue_field (a : expr) (loc : option (block * path)) (f : ident) : option (block * path) :=
  match typeof a, loc with
  | Tstruct _, Some (b, p) => Some (b, p ++ [Sfield f])
  | _, _ => None
  end.

(** The location of [a[i]], given the location of [a] and the value of
    [i]: the index must be within the bounds of the array type of [a]. *)
Definition lvalue_index (a : expr) (loc : option (block * path)) (vi : option val)
  : option (block * path) :=
  match typeof a, loc, vi with
  | Tarray _ n, Some (b, p), Some (Vint k | Vlong k) =>
      if Z.leb 0 k && Z.ltb k n then Some (b, p ++ [Sindex k]) else None
  | _, _, _ => None
  end.

(** Reading a scalar of type [ty] at a location. *)
Definition load_loc (ty : type) (loc : option (block * path)) : option val :=
  match loc with
  | Some (b, p) => load ty m b p
  | None => None
  end.

(** [eval_expr a]: the value of [a] (in r-value position);
    [eval_lvalue a]: the location it designates (in l-value position). *)
Fixpoint eval_expr (a : expr) : option val :=
  match a with
  | Econst_int n (Tint sz sg) => Some (Vint (norm_int sz sg n))
  | Econst_long n (Tlong sg) => Some (Vlong (norm_long sg n))
  | Econst_float f (Tfloat F64) => Some (Vfloat f)
  | Econst_single f (Tfloat F32) => Some (Vsingle f)
  | Econst_int _ _ | Econst_long _ _ | Econst_float _ _ | Econst_single _ _ => None
  | Etempvar x _ => find_assoc x le
  | Evar x (Tfunction _ _) => eval_funcname x
  | Evar x ty => load_loc ty (lvalue_var x)
  | Ederef a1 ty => load_loc ty (lvalue_deref (eval_expr a1))
  | Efield a1 f ty => load_loc ty (lvalue_field a1 (eval_lvalue a1) f)
  | Eindex a1 i ty => load_loc ty (lvalue_index a1 (eval_lvalue a1) (eval_expr i))
  | Eaddrof (Evar x (Tfunction _ _)) _ => eval_funcname x
  | Eaddrof a1 _ =>
      match eval_lvalue a1 with
      | Some (b, p) => Some (Vptr b p)
      | None => None
      end
  | Ecast a1 ty =>
      match eval_expr a1 with
      | Some v => sem_cast v ty
      | None => None
      end
  end

with eval_lvalue (a : expr) : option (block * path) :=
  match a with
  | Evar x (Tfunction _ _) => None
  | Evar x _ => lvalue_var x
  | Ederef a1 _ => lvalue_deref (eval_expr a1)
  | Efield a1 f _ => lvalue_field a1 (eval_lvalue a1) f
  | Eindex a1 i _ => lvalue_index a1 (eval_lvalue a1) (eval_expr i)
  | _ => None
  end.

(** An l-value in r-value position reads the location it designates. *)
Lemma eval_expr_lvalue:
  forall a, match a with
            | Evar _ (Tfunction _ _) => False
            | Evar _ _ | Ederef _ _ | Efield _ _ _ | Eindex _ _ _ => True
            | _ => False
            end ->
  eval_expr a = load_loc (typeof a) (eval_lvalue a).
Proof.
  intros a H; destruct a as [| | | | x ty | | | | | |]; try contradiction; auto.
  destruct ty; try contradiction; reflexivity.
Qed.

(** The arguments of a call, converted to the parameter types. *)
Fixpoint eval_exprlist (al : list expr) (tl : list type) : option (list val) :=
  match al, tl with
  | [], [] => Some []
  | a :: al', t :: tl' =>
      match eval_expr a with
      | Some v =>
          match sem_cast v t, eval_exprlist al' tl' with
          | Some v', Some vl => Some (v' :: vl)
          | _, _ => None
          end
      | None => None
      end
  | _, _ => None
  end.

(** The memory after [a1 = a2]: a scalar assignment converts the value
    to the type of [a1]; an assignment of struct type copies the whole
    struct value. *)
Definition eval_assign (a1 a2 : expr) : option mem :=
  match eval_lvalue a1 with
  | Some (b, p) =>
      match typeof a1 with
      | Tstruct id =>
          match typeof a2, eval_lvalue a2 with
          | Tstruct id', Some (b', p') =>
              if ident_eq id id' then
                match load_path m b' p' with
                | Some mv => store_path m b p mv
                | None => None
                end
              else None
          | _, _ => None
          end
      | ty =>
          match eval_expr a2 with
          | Some v => store ty m b p v
          | None => None
          end
      end
  | None => None
  end.

End EXPR.

(** ** Statements and function calls *)

(** How a statement ends. *)
Inductive outcome : Type :=
  | Out_normal                   (**r fall through *)
  | Out_break                    (**r [break] *)
  | Out_return (v : option val).  (**r [return], with its value *)

(** The value a function returns, given how its body ended. *)
Definition outcome_result (tres : type) (out : outcome) : option val :=
  match out with
  | Out_normal => Some Vundef
  | Out_return None => Some Vundef
  | Out_return (Some v) => sem_cast v tres
  | Out_break => None
  end.

(** What a loop body's outcome means for the loop. *)
Definition loop_outcome (out : outcome) : outcome :=
  match out with
  | Out_break => Out_normal
  | o => o
  end.

Definition set_opttemp (optid : option ident) (v : val) (le : temp_env) : temp_env :=
  match optid with
  | Some x => set_assoc x v le
  | None => le
  end.

(** Allocate the addressable locals of a function, with unspecified
    contents of the right shape. *)
Fixpoint alloc_vars (ce : composite_env) (e : env) (m : mem) (vars : list (ident * type)) : env * mem :=
  match vars with
  | [] => (e, m)
  | (x, ty) :: vars' =>
      let (m1, b) := alloc m ty (undef_mval ce ty) in
      alloc_vars ce (set_assoc x (b, ty) e) m1 vars'
  end.

(** Free the blocks of the locals. *)
Fixpoint free_vars (m : mem) (e : env) : mem :=
  match e with
  | [] => m
  | (_, (b, _)) :: e' => free_vars (free m b) e'
  end.

(** Temporaries start unspecified; parameters are temporaries bound to the
    arguments. *)
Fixpoint bind_params (params : list (ident * type)) (vargs : list val) (le : temp_env)
  : option temp_env :=
  match params, vargs with
  | [], [] => Some le
  | (x, _) :: params', v :: vargs' => bind_params params' vargs' (set_assoc x v le)
  | _, _ => None
  end.

Definition create_undef_temps (temps : list (ident * type)) : temp_env :=
  fold_left (fun le xt => set_assoc (fst xt) Vundef le) temps [].

Definition function_entry (ce : composite_env) (f : function) (vargs : list val) (m : mem)
  : option (env * temp_env * mem) :=
  let (e, m1) := alloc_vars ce [] m (fn_vars f) in
  match bind_params (fn_params f) vargs (create_undef_temps (fn_temps f)) with
  | Some le => Some (e, le, m1)
  | None => None
  end.

Section SEMANTICS.

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
  | EF_ros_rate_sleep, [] => Some (Vundef, [Ecycle], m, w)
  | EF_ros_subscribe topic msgty q, [Vfptr cb] =>
      Some (Vundef, [], m, add_subscription w (mksub topic msgty q cb))
  | EF_ros_advertise topic _ _, [] => Some (Vundef, [], m, add_advertised w topic)
  | EF_ros_publish topic _, [Vptr b p] =>
      if existsb (topic_eqb topic) (w_advertised w) then
        match load_path m b p with
        | Some mv => Some (Vundef, [Epublish topic mv], m, w)
        | None => None
        end
      else None
  | EF_controller_initialize _ _, [] => Some (Vundef, [], m, set_ctrl w (ctx_init ctx))
  | EF_controller_step u y, [] =>
      match find_var ge u, find_var ge y with
      | Some (bu, _), Some (by_, ty) =>
          match load_path m bu [] with
          | Some uv =>
              let (s', yv) := ctx_step ctx (w_ctrl w) uv in
              if mval_typecheck (ge_comp ge) ty yv then
                match store_path m by_ [] yv with
                | Some m' => Some (Vundef, [Estep uv yv], m', set_ctrl w s')
                | None => None
                end
              else None
          | None => None
          end
      | _, _ => None
      end
  | _, _ => None
  end.

(** The messages one [ros_spinOnce] delivers. *)
Definition spin_messages (w : world CS) : list (subscription * mval) :=
  deliverable (w_subs w) (ctx_arrivals ctx (w_spins w)).

(** [exec_stmt e le m w s t le' m' w' out]: statement [s], started with
    locals [e], temporaries [le], memory [m] and world [w], terminates
    with events [t], temporaries [le'], memory [m'], world [w'], ending
    as [out].

    [eval_funcall m w fd args t m' w' v]: calling [fd] with [args]
    terminates with events [t] and returns [v].

    [deliver m w msgs t m' w']: running the callbacks of [msgs] in order,
    each on a fresh copy of its message, terminates with events [t]. *)
Inductive exec_stmt : env -> temp_env -> mem -> world CS -> statement ->
                      trace -> temp_env -> mem -> world CS -> outcome -> Prop :=
  | exec_Sskip: forall e le m w,
      exec_stmt e le m w Sskip [] le m w Out_normal
  | exec_Sassign: forall e le m w a1 a2 m',
      eval_assign ge e le m a1 a2 = Some m' ->
      exec_stmt e le m w (Sassign a1 a2) [] le m' w Out_normal
  | exec_Sset: forall e le m w x a v,
      eval_expr ge e le m a = Some v ->
      exec_stmt e le m w (Sset x a) [] (set_assoc x v le) m w Out_normal
  | exec_Scall: forall e le m w optid a al fid fd targs tres vargs t m' w' vres,
      eval_expr ge e le m a = Some (Vfptr fid) ->
      find_funct ge fid = Some fd ->
      typeof a = Tfunction targs tres ->
      type_of_fundef fd = Tfunction targs tres ->
      eval_exprlist ge e le m al targs = Some vargs ->
      eval_funcall m w fd vargs t m' w' vres ->
      exec_stmt e le m w (Scall optid a al) t (set_opttemp optid vres le) m' w' Out_normal
  | exec_Sseq_1: forall e le m w s1 s2 t1 le1 m1 w1 t2 le2 m2 w2 out,
      exec_stmt e le m w s1 t1 le1 m1 w1 Out_normal ->
      exec_stmt e le1 m1 w1 s2 t2 le2 m2 w2 out ->
      exec_stmt e le m w (Ssequence s1 s2) (t1 ++ t2) le2 m2 w2 out
  | exec_Sseq_2: forall e le m w s1 s2 t1 le1 m1 w1 out,
      exec_stmt e le m w s1 t1 le1 m1 w1 out ->
      out <> Out_normal ->
      exec_stmt e le m w (Ssequence s1 s2) t1 le1 m1 w1 out
  | exec_Sifthenelse: forall e le m w a s1 s2 v b t le' m' w' out,
      eval_expr ge e le m a = Some v ->
      bool_val v = Some b ->
      exec_stmt e le m w (if b then s1 else s2) t le' m' w' out ->
      exec_stmt e le m w (Sifthenelse a s1 s2) t le' m' w' out
  | exec_Sbreak: forall e le m w,
      exec_stmt e le m w Sbreak [] le m w Out_break
  | exec_Sreturn_none: forall e le m w,
      exec_stmt e le m w (Sreturn None) [] le m w (Out_return None)
  | exec_Sreturn_some: forall e le m w a v,
      eval_expr ge e le m a = Some v ->
      exec_stmt e le m w (Sreturn (Some a)) [] le m w (Out_return (Some v))
  | exec_Sloop_loop: forall e le m w s t1 le1 m1 w1 t2 le2 m2 w2 out,
      exec_stmt e le m w s t1 le1 m1 w1 Out_normal ->
      exec_stmt e le1 m1 w1 (Sloop s) t2 le2 m2 w2 out ->
      exec_stmt e le m w (Sloop s) (t1 ++ t2) le2 m2 w2 out
  | exec_Sloop_stop: forall e le m w s t le' m' w' out,
      exec_stmt e le m w s t le' m' w' out ->
      out <> Out_normal ->
      exec_stmt e le m w (Sloop s) t le' m' w' (loop_outcome out)

with eval_funcall : mem -> world CS -> fundef -> list val ->
                    trace -> mem -> world CS -> val -> Prop :=
  | eval_funcall_internal: forall m w f vargs e le m1 t le' m2 w' out vres,
      function_entry (ge_comp ge) f vargs m = Some (e, le, m1) ->
      exec_stmt e le m1 w (fn_body f) t le' m2 w' out ->
      outcome_result (fn_return f) out = Some vres ->
      eval_funcall m w (Internal f) vargs t (free_vars m2 e) w' vres
  | eval_funcall_external: forall ef targs tres vargs m w vres t m' w',
      external_call ef vargs m w = Some (vres, t, m', w') ->
      eval_funcall m w (External ef targs tres) vargs t m' w' vres
  | eval_funcall_spinOnce: forall targs tres m w t m' w',
      deliver m w (spin_messages w) t m' w' ->
      eval_funcall m w (External EF_ros_spinOnce targs tres) [] t m' (next_spin w') Vundef

with deliver : mem -> world CS -> list (subscription * mval) ->
               trace -> mem -> world CS -> Prop :=
  | deliver_nil: forall m w,
      deliver m w [] [] m w
  | deliver_cons: forall m w s mv rest m1 b fd t1 m2 w1 v t2 m3 w2,
      alloc m (Tstruct (sub_msgty s)) mv = (m1, b) ->
      find_funct ge (sub_callback s) = Some fd ->
      eval_funcall m1 w fd [Vptr b []] t1 m2 w1 v ->
      deliver (free m2 b) w1 rest t2 m3 w2 ->
      deliver m w ((s, mv) :: rest) (t1 ++ t2) m3 w2.

Scheme exec_stmt_ind3 := Minimality for exec_stmt Sort Prop
  with eval_funcall_ind3 := Minimality for eval_funcall Sort Prop
  with deliver_ind3 := Minimality for deliver Sort Prop.
Combined Scheme exec_stmt_funcall_deliver_ind from exec_stmt_ind3, eval_funcall_ind3, deliver_ind3.

Lemma external_call_not_spin:
  forall vargs m w r, external_call EF_ros_spinOnce vargs m w = Some r -> False.
Proof. intros vargs m w r H; destruct vargs; discriminate. Qed.

End SEMANTICS.

(** ** Programs *)

(** The global environment and initial memory of a program: each global
    variable gets its own block, zero-initialised (C static storage);
    functions are recorded by name. *)
Fixpoint alloc_globals (ge : genv) (m : mem) (defs : list (ident * globdef)) : genv * mem :=
  match defs with
  | [] => (ge, m)
  | (x, Gfun fd) :: defs' =>
      alloc_globals (mkgenv (ge_comp ge) (ge_vars ge) ((x, fd) :: ge_funs ge)) m defs'
  | (x, Gvar ty) :: defs' =>
      let (m1, b) := alloc m ty (zero_mval (ge_comp ge) ty) in
      alloc_globals (mkgenv (ge_comp ge) ((x, (b, ty)) :: ge_vars ge) (ge_funs ge)) m1 defs'
  end.

Definition globalenv_mem (p : program) : genv * mem :=
  alloc_globals (mkgenv (prog_types p) [] []) empty (prog_defs p).

Definition globalenv (p : program) : genv := fst (globalenv_mem p).
Definition init_mem (p : program) : mem := snd (globalenv_mem p).

(** [program_behaves p ctx n t]: in the environment [ctx], where
    [ros_ok] answers true [n] times and then false, [main] terminates and
    the run produces the events [t]. *)
Inductive program_behaves {CS : Type} (p : program) (ctx : ros_context CS) (n : nat) (t : trace)
  : Prop :=
  | program_runs: forall fd m' w' v,
      find_funct (globalenv p) (prog_main p) = Some fd ->
      eval_funcall ctx (globalenv p) (init_mem p) (initial_world ctx n) fd [] t m' w' v ->
      program_behaves p ctx n t.

(** ** Well-typed programs *)

(** What the generator establishes for its output: struct definitions
    are well formed, names are unique, every variable is declared with the
    type its occurrences carry, assignments are between equal types, calls
    match the callee's type, field accesses name existing members with
    their types, array subscripts have integer type, and external
    functions are declared with the signature of their meaning.
    [wt_program] is the specification, [check_program] its decision
    procedure ([check_program_correct]). *)

(** The typing context of a function body. *)
Record typenv : Type := mktypenv {
  te_comp : composite_env;
  te_vars : list (ident * type);    (**r addressable locals, then global variables *)
  te_funs : list (ident * type);    (**r the functions and their types *)
  te_temps : list (ident * type);   (**r parameters and temporaries *)
  te_return : type                  (**r the return type *)
}.

Definition is_int_type (ty : type) : bool :=
  match ty with Tint _ _ | Tlong _ => true | _ => false end.

Definition is_struct_type (ty : type) : bool :=
  match ty with Tstruct _ => true | _ => false end.

Definition is_function_type (ty : type) : bool :=
  match ty with Tfunction _ _ => true | _ => false end.

(** Expressions that designate an object. *)
Definition is_lvalue (a : expr) : bool :=
  match a with
  | Evar _ (Tfunction _ _) => false
  | Evar _ _ | Ederef _ _ | Efield _ _ _ | Eindex _ _ _ => true
  | _ => false
  end.

(** Expressions that designate a function. *)
Definition is_fundesignator (a : expr) : bool :=
  match a with
  | Evar _ (Tfunction _ _) => true
  | _ => false
  end.

(** The casts the semantics defines: between integer types, and from a
    scalar type to itself. *)
Definition cast_ok (from to : type) : bool :=
  (is_int_type from && is_int_type to) || (is_scalar_type to && type_eqb from to).

(** An argument of type [ta] for a parameter of type [t]: the same scalar
    type, or a function designator for a function pointer. *)
Definition arg_type_ok (ta t : type) : bool :=
  (is_scalar_type ta && type_eqb ta t) || (is_function_type ta && type_eqb t (Tpointer ta)).

Section TYPING.

Variable te : typenv.

Inductive wt_expr : expr -> Prop :=
  | wt_Econst_int: forall n sz sg, wt_expr (Econst_int n (Tint sz sg))
  | wt_Econst_long: forall n sg, wt_expr (Econst_long n (Tlong sg))
  | wt_Econst_float: forall f, wt_expr (Econst_float f (Tfloat F64))
  | wt_Econst_single: forall f, wt_expr (Econst_single f (Tfloat F32))
  | wt_Evar: forall x ty,
      find_assoc x (te_vars te) = Some ty ->
      wt_expr (Evar x ty)
  | wt_Evar_fun: forall x targs tres,
      find_assoc x (te_vars te) = None ->
      find_assoc x (te_funs te) = Some (Tfunction targs tres) ->
      wt_expr (Evar x (Tfunction targs tres))
  | wt_Etempvar: forall x ty,
      find_assoc x (te_temps te) = Some ty ->
      wt_expr (Etempvar x ty)
  | wt_Ederef: forall a ty,
      wt_expr a -> typeof a = Tpointer ty ->
      complete_type (composite_names (te_comp te)) ty = true ->
      wt_expr (Ederef a ty)
  | wt_Eaddrof: forall a,
      wt_expr a -> is_lvalue a || is_fundesignator a = true ->
      wt_expr (Eaddrof a (Tpointer (typeof a)))
  | wt_Efield: forall a f id members ty,
      wt_expr a -> is_lvalue a = true -> typeof a = Tstruct id ->
      struct_members (te_comp te) id = Some members ->
      field_type f members = Some ty ->
      wt_expr (Efield a f ty)
  | wt_Eindex: forall a i ty n,
      wt_expr a -> is_lvalue a = true -> typeof a = Tarray ty n ->
      wt_expr i -> is_int_type (typeof i) = true ->
      wt_expr (Eindex a i ty)
  | wt_Ecast: forall a ty,
      wt_expr a -> cast_ok (typeof a) ty = true ->
      wt_expr (Ecast a ty).

Inductive wt_exprlist : list expr -> list type -> Prop :=
  | wt_Enil: wt_exprlist [] []
  | wt_Econs: forall a al t tl,
      wt_expr a -> arg_type_ok (typeof a) t = true -> wt_exprlist al tl ->
      wt_exprlist (a :: al) (t :: tl).

Definition wt_opttemp (optid : option ident) (tres : type) : Prop :=
  match optid with
  | None => True
  | Some x => find_assoc x (te_temps te) = Some tres
  end.

Inductive wt_stmt : statement -> Prop :=
  | wt_Sskip: wt_stmt Sskip
  | wt_Sassign: forall a1 a2,
      wt_expr a1 -> wt_expr a2 -> is_lvalue a1 = true -> typeof a1 = typeof a2 ->
      is_scalar_type (typeof a1) || (is_struct_type (typeof a1) && is_lvalue a2) = true ->
      wt_stmt (Sassign a1 a2)
  | wt_Sset: forall x a,
      wt_expr a -> is_scalar_type (typeof a) = true ->
      find_assoc x (te_temps te) = Some (typeof a) ->
      wt_stmt (Sset x a)
  | wt_Scall: forall optid a al targs tres,
      wt_expr a -> typeof a = Tfunction targs tres ->
      wt_exprlist al targs -> wt_opttemp optid tres ->
      wt_stmt (Scall optid a al)
  | wt_Ssequence: forall s1 s2, wt_stmt s1 -> wt_stmt s2 -> wt_stmt (Ssequence s1 s2)
  | wt_Sifthenelse: forall a s1 s2,
      wt_expr a -> is_scalar_type (typeof a) = true -> wt_stmt s1 -> wt_stmt s2 ->
      wt_stmt (Sifthenelse a s1 s2)
  | wt_Sloop: forall s, wt_stmt s -> wt_stmt (Sloop s)
  | wt_Sbreak: wt_stmt Sbreak
  | wt_Sreturn_none: te_return te = Tvoid -> wt_stmt (Sreturn None)
  | wt_Sreturn_some: forall a,
      wt_expr a -> is_scalar_type (typeof a) = true -> cast_ok (typeof a) (te_return te) = true ->
      wt_stmt (Sreturn (Some a)).

(** The decision procedures. *)

Fixpoint check_expr (a : expr) : bool :=
  match a with
  | Econst_int _ (Tint _ _) | Econst_long _ (Tlong _)
  | Econst_float _ (Tfloat F64) | Econst_single _ (Tfloat F32) => true
  | Econst_int _ _ | Econst_long _ _ | Econst_float _ _ | Econst_single _ _ => false
  | Evar x ty =>
      match find_assoc x (te_vars te) with
      | Some ty' => type_eqb ty ty'
      | None =>
          is_function_type ty &&
          match find_assoc x (te_funs te) with
          | Some ty' => type_eqb ty ty'
          | None => false
          end
      end
  | Etempvar x ty =>
      match find_assoc x (te_temps te) with
      | Some ty' => type_eqb ty ty'
      | None => false
      end
  | Ederef a1 ty =>
      check_expr a1 && type_eqb (typeof a1) (Tpointer ty)
      && complete_type (composite_names (te_comp te)) ty
  | Eaddrof a1 ty =>
      check_expr a1 && (is_lvalue a1 || is_fundesignator a1) && type_eqb ty (Tpointer (typeof a1))
  | Efield a1 f ty =>
      check_expr a1 && is_lvalue a1 &&
      match typeof a1 with
      | Tstruct id =>
          match struct_members (te_comp te) id with
          | Some members =>
              match field_type f members with
              | Some ty' => type_eqb ty' ty
              | None => false
              end
          | None => false
          end
      | _ => false
      end
  | Eindex a1 i ty =>
      check_expr a1 && is_lvalue a1 && check_expr i && is_int_type (typeof i) &&
      match typeof a1 with
      | Tarray ty' _ => type_eqb ty' ty
      | _ => false
      end
  | Ecast a1 ty => check_expr a1 && cast_ok (typeof a1) ty
  end.

Fixpoint check_exprlist (al : list expr) (tl : list type) : bool :=
  match al, tl with
  | [], [] => true
  | a :: al', t :: tl' => check_expr a && arg_type_ok (typeof a) t && check_exprlist al' tl'
  | _, _ => false
  end.

Definition check_opttemp (optid : option ident) (tres : type) : bool :=
  match optid with
  | None => true
  | Some x =>
      match find_assoc x (te_temps te) with
      | Some t => type_eqb t tres
      | None => false
      end
  end.

Fixpoint check_stmt (s : statement) : bool :=
  match s with
  | Sskip | Sbreak => true
  | Sassign a1 a2 =>
      check_expr a1 && check_expr a2 && is_lvalue a1 && type_eqb (typeof a1) (typeof a2)
      && (is_scalar_type (typeof a1) || (is_struct_type (typeof a1) && is_lvalue a2))
  | Sset x a =>
      check_expr a && is_scalar_type (typeof a) &&
      match find_assoc x (te_temps te) with
      | Some t => type_eqb t (typeof a)
      | None => false
      end
  | Scall optid a al =>
      check_expr a &&
      match typeof a with
      | Tfunction targs tres => check_exprlist al targs && check_opttemp optid tres
      | _ => false
      end
  | Ssequence s1 s2 => check_stmt s1 && check_stmt s2
  | Sifthenelse a s1 s2 =>
      check_expr a && is_scalar_type (typeof a) && check_stmt s1 && check_stmt s2
  | Sloop s1 => check_stmt s1
  | Sreturn None => type_eqb (te_return te) Tvoid
  | Sreturn (Some a) =>
      check_expr a && is_scalar_type (typeof a) && cast_ok (typeof a) (te_return te)
  end.

Local Ltac split_andb :=
  repeat match goal with
  | H : (_ && _) = true |- _ => apply andb_prop in H; destruct H
  | H : type_eqb _ _ = true |- _ => apply type_eqb_true in H; subst
  end.

Lemma check_expr_correct: forall a, check_expr a = true -> wt_expr a.
Proof.
  induction a as [n ty | n ty | f ty | f ty | x ty | x ty | a1 IH1 ty | a1 IH1 ty
                 | a1 IH1 f ty | a1 IH1 i IHi ty | a1 IH1 ty]; simpl; intros H.
  - destruct ty; try discriminate; constructor.
  - destruct ty; try discriminate; constructor.
  - destruct ty as [| | | [|] | | | |]; try discriminate; constructor.
  - destruct ty as [| | | [|] | | | |]; try discriminate; constructor.
  - destruct (find_assoc x (te_vars te)) as [ty'|] eqn:V.
    + split_andb. constructor; auto.
    + destruct ty; try discriminate. simpl in H.
      destruct (find_assoc x (te_funs te)) as [ty'|] eqn:F; try discriminate.
      split_andb. apply wt_Evar_fun; auto.
  - destruct (find_assoc x (te_temps te)) as [ty'|] eqn:V; try discriminate.
    split_andb. constructor; auto.
  - split_andb. econstructor; eauto.
  - split_andb. constructor; auto.
  - split_andb. destruct (typeof a1) as [| | | | | | | id] eqn:T; try discriminate.
    destruct (struct_members (te_comp te) id) as [members|] eqn:SM; try discriminate.
    destruct (field_type f members) as [ty'|] eqn:FT; try discriminate.
    split_andb. econstructor; eauto.
  - split_andb. destruct (typeof a1) as [| | | | | t n | |] eqn:T; try discriminate.
    split_andb. econstructor; eauto.
  - split_andb. constructor; auto.
Qed.

Lemma check_exprlist_correct:
  forall al tl, check_exprlist al tl = true -> wt_exprlist al tl.
Proof.
  induction al as [|a al IH]; destruct tl as [|t tl]; simpl; intros H; try discriminate.
  - constructor.
  - split_andb. constructor; auto. apply check_expr_correct; auto.
Qed.

Lemma check_stmt_correct: forall s, check_stmt s = true -> wt_stmt s.
Proof.
  induction s as [| a1 a2 | x a | optid a al | s1 IH1 s2 IH2 | a s1 IH1 s2 IH2 | s IH | | [a|]];
    simpl; intros H; split_andb.
  - constructor.
  - constructor; auto using check_expr_correct.
  - destruct (find_assoc x (te_temps te)) as [t|] eqn:T; try discriminate.
    split_andb. constructor; auto using check_expr_correct.
  - destruct (typeof a) as [| | | | | | targs tres |] eqn:T; try discriminate.
    split_andb. econstructor; eauto using check_expr_correct, check_exprlist_correct.
    destruct optid as [x|]; simpl in *; auto.
    destruct (find_assoc x (te_temps te)) as [t|]; try discriminate. split_andb; auto.
  - constructor; auto.
  - constructor; auto using check_expr_correct.
  - constructor; auto.
  - constructor.
  - constructor; auto using check_expr_correct.
  - constructor; auto.
Qed.

End TYPING.

(** The signature that the meaning of each external function requires. *)
Definition ef_signature (ef : external_function) : list type * type :=
  match ef with
  | EF_ros_init | EF_ros_spinOnce | EF_ros_rate_sleep => ([], Tvoid)
  | EF_ros_ok => ([], tint)
  | EF_ros_subscribe _ msgty _ => ([tptr (Tfunction [tptr (Tstruct msgty)] Tvoid)], Tvoid)
  | EF_ros_advertise _ _ _ => ([], Tvoid)
  | EF_ros_publish _ msgty => ([tptr (Tstruct msgty)], Tvoid)
  | EF_controller_initialize _ _ | EF_controller_step _ _ => ([], Tvoid)
  end.

(** The global variables and the functions of a program, with their
    types. *)
Definition global_vars (p : program) : list (ident * type) :=
  flat_map (fun d => match snd d with Gvar ty => [(fst d, ty)] | Gfun _ => [] end) (prog_defs p).

Definition global_funs (p : program) : list (ident * type) :=
  flat_map (fun d => match snd d with Gfun fd => [(fst d, type_of_fundef fd)] | Gvar _ => [] end)
           (prog_defs p).

(** The typing context of the body of [f] in [p]. *)
Definition function_typenv (p : program) (f : function) : typenv :=
  mktypenv (prog_types p) (fn_vars f ++ global_vars p) (global_funs p)
           (fn_params f ++ fn_temps f) (fn_return f).

(** The local names of a function. *)
Definition local_names (f : function) : list ident :=
  map fst (fn_params f ++ fn_temps f ++ fn_vars f).

(** A well-typed function: its local names are distinct and hide no
    global (so that the printed C means the same), parameters and
    temporaries are scalars, locals have complete types, the return type
    is [void] or a scalar, and the body is well typed. *)
Definition wt_function (p : program) (f : function) : Prop :=
  NoDup (local_names f)
  /\ (forall x, In x (local_names f) -> ~ In x (map fst (prog_defs p)))
  /\ (forall x t, In (x, t) (fn_params f ++ fn_temps f) -> is_scalar_type t = true)
  /\ (forall x t, In (x, t) (fn_vars f) -> complete_type (composite_names (prog_types p)) t = true)
  /\ (fn_return f = Tvoid \/ is_scalar_type (fn_return f) = true)
  /\ wt_stmt (function_typenv p f) (fn_body f).

(** A well-typed external declaration: it has the signature of its
    meaning; message types are defined structs; the controller's globals
    are global variables of struct type. *)
Definition wt_external (p : program) (ef : external_function) (targs : list type) (tres : type) : Prop :=
  ef_signature ef = (targs, tres)
  /\ match ef with
     | EF_ros_subscribe _ msgty _ | EF_ros_advertise _ msgty _ | EF_ros_publish _ msgty =>
         struct_members (prog_types p) msgty <> None
     | EF_controller_initialize u y | EF_controller_step u y =>
         (exists id, find_assoc u (global_vars p) = Some (Tstruct id))
         /\ (exists id, find_assoc y (global_vars p) = Some (Tstruct id))
     | _ => True
     end.

Record wt_program (p : program) : Prop := {
  wt_prog_composites: wf_composites (prog_types p);
  wt_prog_names: NoDup (map fst (prog_defs p));
  wt_prog_vars: forall x ty, In (x, Gvar ty) (prog_defs p) ->
                complete_type (composite_names (prog_types p)) ty = true;
  wt_prog_internal: forall x f, In (x, Gfun (Internal f)) (prog_defs p) -> wt_function p f;
  wt_prog_external: forall x ef targs tres, In (x, Gfun (External ef targs tres)) (prog_defs p) ->
                    wt_external p ef targs tres;
  wt_prog_main: exists fd, find_def p (prog_main p) = Some (Gfun fd)
                           /\ type_of_fundef fd = Tfunction [] tint
}.

(** The decision procedure for programs. *)

Definition check_function (p : program) (f : function) : bool :=
  nodup_idents (local_names f)
  && forallb (fun x => negb (in_ident x (map fst (prog_defs p)))) (local_names f)
  && forallb (fun xt => is_scalar_type (snd xt)) (fn_params f ++ fn_temps f)
  && forallb (fun xt => complete_type (composite_names (prog_types p)) (snd xt)) (fn_vars f)
  && (type_eqb (fn_return f) Tvoid || is_scalar_type (fn_return f))
  && check_stmt (function_typenv p f) (fn_body f).

Definition is_struct_var (p : program) (x : ident) : bool :=
  match find_assoc x (global_vars p) with
  | Some (Tstruct _) => true
  | _ => false
  end.

Definition check_external (p : program) (ef : external_function) (targs : list type) (tres : type) : bool :=
  let (sargs, sres) := ef_signature ef in
  (if list_eq_dec type_eq targs sargs then true else false) && type_eqb tres sres
  && match ef with
     | EF_ros_subscribe _ msgty _ | EF_ros_advertise _ msgty _ | EF_ros_publish _ msgty =>
         match struct_members (prog_types p) msgty with Some _ => true | None => false end
     | EF_controller_initialize u y | EF_controller_step u y =>
         is_struct_var p u && is_struct_var p y
     | _ => true
     end.

Definition check_globdef (p : program) (d : ident * globdef) : bool :=
  match snd d with
  | Gvar ty => complete_type (composite_names (prog_types p)) ty
  | Gfun (Internal f) => check_function p f
  | Gfun (External ef targs tres) => check_external p ef targs tres
  end.

Definition check_program (p : program) : bool :=
  composites_ok [] (prog_types p)
  && nodup_idents (map fst (prog_defs p))
  && forallb (check_globdef p) (prog_defs p)
  && match find_def p (prog_main p) with
     | Some (Gfun fd) => type_eqb (type_of_fundef fd) (Tfunction [] tint)
     | _ => false
     end.

Lemma check_function_correct: forall p f, check_function p f = true -> wt_function p f.
Proof.
  unfold check_function, wt_function; intros p f H.
  repeat (apply andb_prop in H; destruct H as [H ?]).
  repeat match goal with
  | H : forallb _ _ = true |- _ => rewrite forallb_forall in H
  end.
  split; [apply nodup_idents_spec; auto|].
  split; [intros x Hx; rewrite <- in_ident_spec;
          match goal with H : forall x, In x (local_names f) -> _ |- _ =>
            specialize (H x Hx); apply negb_true_iff in H; congruence end|].
  split; [intros x t Hin; match goal with H : forall x, In x (fn_params f ++ fn_temps f) -> _ |- _ => apply (H (x, t) Hin) end|].
  split; [intros x t Hin; match goal with H : forall x, In x (fn_vars f) -> _ |- _ => apply (H (x, t) Hin) end|].
  split; [|apply check_stmt_correct; auto].
  match goal with H : type_eqb _ _ || _ = true |- _ => apply orb_prop in H; destruct H as [H|H] end;
    [left; apply type_eqb_true; auto | right; auto].
Qed.

Lemma check_external_correct:
  forall p ef targs tres, check_external p ef targs tres = true -> wt_external p ef targs tres.
Proof.
  unfold check_external, wt_external; intros p ef targs tres H.
  destruct (ef_signature ef) as [sargs sres] eqn:SIG.
  apply andb_prop in H as [H H3]. apply andb_prop in H as [H1 H2].
  destruct (list_eq_dec type_eq targs sargs) as [E|]; try discriminate. subst sargs.
  apply type_eqb_true in H2. subst sres. split; auto.
  destruct ef; auto;
    try (destruct (struct_members (prog_types p) msgty); [discriminate | discriminate]);
    unfold is_struct_var in H3; apply andb_prop in H3 as [Hu Hy].
  - split.
    + destruct (find_assoc inputs (global_vars p)) as [[]|]; try discriminate; eauto.
    + destruct (find_assoc outputs (global_vars p)) as [[]|]; try discriminate; eauto.
  - split.
    + destruct (find_assoc inputs (global_vars p)) as [[]|]; try discriminate; eauto.
    + destruct (find_assoc outputs (global_vars p)) as [[]|]; try discriminate; eauto.
Qed.

Theorem check_program_correct: forall p, check_program p = true -> wt_program p.
Proof.
  unfold check_program; intros p H.
  apply andb_prop in H as [H H4]. apply andb_prop in H as [H H3]. apply andb_prop in H as [H1 H2].
  rewrite forallb_forall in H3.
  constructor.
  - exact H1.
  - apply nodup_idents_spec; auto.
  - intros x ty Hin. apply (H3 _ Hin).
  - intros x f Hin. apply check_function_correct, (H3 _ Hin).
  - intros x ef targs tres Hin. apply check_external_correct, (H3 _ Hin).
  - destruct (find_def p (prog_main p)) as [[fd|]|]; try discriminate.
    exists fd; split; auto. apply type_eqb_true; auto.
Qed.

(** ** Properties of the initial state *)

Lemma find_assoc_In:
  forall (A : Type) x (v : A) l, find_assoc x l = Some v -> In (x, v) l.
Proof.
  induction l as [|[y w] l IH]; simpl; intros H; try discriminate.
  destruct (string_dec x y); [inversion H; subst; auto | auto].
Qed.

Lemma In_find_assoc:
  forall (A : Type) x (v : A) l, NoDup (map fst l) -> In (x, v) l -> find_assoc x l = Some v.
Proof.
  induction l as [|[y w] l IH]; simpl; intros ND H; [contradiction|].
  inversion ND as [|? ? Hy ND']; subst.
  destruct H as [H|H].
  - inversion H; subst. destruct (string_dec x x); congruence.
  - destruct (string_dec x y) as [E|N]; auto.
    subst; exfalso; apply Hy. apply (in_map fst _ _ H).
Qed.

(** The names of the global variables, resp. functions, of a list of
    definitions. *)
Definition var_names (defs : list (ident * globdef)) : list ident :=
  flat_map (fun d => match snd d with Gvar _ => [fst d] | Gfun _ => [] end) defs.

Definition fun_defs (defs : list (ident * globdef)) : list (ident * fundef) :=
  flat_map (fun d => match snd d with Gfun fd => [(fst d, fd)] | Gvar _ => [] end) defs.

(** The invariant of [alloc_globals]: every global's block holds its zero
    value, below [mem_next]; different entries have different blocks. *)
Definition globals_inv (ge : genv) (m : mem) : Prop :=
  mem_wf m
  /\ (forall x b ty, In (x, (b, ty)) (ge_vars ge) ->
        get_block m b = Some (ty, zero_mval (ge_comp ge) ty) /\ (b < mem_next m)%positive)
  /\ NoDup (map (fun xv => fst (snd xv)) (ge_vars ge)).

Lemma alloc_globals_inv:
  forall defs ge m ge' m', globals_inv ge m -> alloc_globals ge m defs = (ge', m') ->
  globals_inv ge' m'
  /\ ge_comp ge' = ge_comp ge
  /\ map fst (ge_vars ge') = rev (var_names defs) ++ map fst (ge_vars ge)
  /\ ge_funs ge' = rev (fun_defs defs) ++ ge_funs ge
  /\ (forall x b ty, In (x, (b, ty)) (ge_vars ge') ->
        In (x, (b, ty)) (ge_vars ge) \/ In (x, Gvar ty) defs).
Proof.
  induction defs as [|[x [fd|ty]] defs IH]; intros ge m ge' m' INV H; cbn [alloc_globals] in H.
  - inversion H; subst. refine (conj INV (conj eq_refl (conj eq_refl (conj eq_refl _)))); auto.
  - change (var_names ((x, Gfun fd) :: defs)) with (var_names defs).
    change (fun_defs ((x, Gfun fd) :: defs)) with ((x, fd) :: fun_defs defs).
    set (ge1 := mkgenv (ge_comp ge) (ge_vars ge) ((x, fd) :: ge_funs ge)) in H.
    assert (INV1: globals_inv ge1 m) by exact INV.
    destruct (IH _ _ _ _ INV1 H) as [A [B [C [D E]]]]. simpl in B, C, D, E.
    refine (conj A (conj B (conj C (conj _ _)))).
    + rewrite D. simpl. rewrite <- app_assoc. reflexivity.
    + intros y b ty Hin. destruct (E y b ty Hin); simpl; auto.
  - change (var_names ((x, Gvar ty) :: defs)) with (x :: var_names defs).
    change (fun_defs ((x, Gvar ty) :: defs)) with (fun_defs defs).
    destruct (alloc m ty (zero_mval (ge_comp ge) ty)) as [m1 b] eqn:AL.
    destruct INV as [W [G ND]].
    assert (INV1: globals_inv (mkgenv (ge_comp ge) ((x, (b, ty)) :: ge_vars ge) (ge_funs ge)) m1).
    { split; [eapply mem_wf_alloc; eauto|]. split.
      - simpl. intros y b' ty' [Hin|Hin].
        + inversion Hin; subst. split; [eapply get_block_alloc_same; eauto|].
          rewrite (alloc_next _ _ _ _ _ AL), (alloc_result _ _ _ _ _ AL). lia.
        + destruct (G _ _ _ Hin) as [G1 G2].
          assert (b' <> b) by (rewrite (alloc_result _ _ _ _ _ AL); lia).
          split; [rewrite (get_block_alloc_other _ _ _ _ _ _ AL); auto|].
          rewrite (alloc_next _ _ _ _ _ AL). lia.
      - simpl. constructor; auto. intros Hin. apply in_map_iff in Hin as [[y [b' ty']] [Eb Hin]].
        simpl in Eb; subst b'. destruct (G _ _ _ Hin) as [_ Hlt].
        rewrite (alloc_result _ _ _ _ _ AL) in Hlt. lia. }
    destruct (IH _ _ _ _ INV1 H) as [A [B [C [D E]]]]. simpl in B, C, D, E.
    refine (conj A (conj B (conj _ (conj D _)))).
    + rewrite C. simpl. rewrite <- app_assoc. reflexivity.
    + intros y b' ty' Hin. destruct (E y b' ty' Hin) as [[Hin'|Hin']|Hin']; simpl; auto.
      inversion Hin'; subst; auto.
Qed.

Lemma globals_inv_empty: forall ce, globals_inv (mkgenv ce [] []) empty.
Proof.
  intros ce; split; [apply mem_wf_empty|]. split; [simpl; tauto|]. constructor.
Qed.

Lemma globalenv_props:
  forall p,
  globals_inv (globalenv p) (init_mem p)
  /\ ge_comp (globalenv p) = prog_types p
  /\ map fst (ge_vars (globalenv p)) = rev (var_names (prog_defs p))
  /\ ge_funs (globalenv p) = rev (fun_defs (prog_defs p))
  /\ (forall x b ty, In (x, (b, ty)) (ge_vars (globalenv p)) -> In (x, Gvar ty) (prog_defs p)).
Proof.
  intros p. unfold globalenv, init_mem, globalenv_mem.
  destruct (alloc_globals (mkgenv (prog_types p) [] []) empty (prog_defs p)) as [ge m] eqn:AG.
  destruct (alloc_globals_inv _ _ _ _ _ (globals_inv_empty (prog_types p)) AG) as [A [B [C [D E]]]].
  simpl in *. rewrite app_nil_r in C, D. split; auto. split; auto. split; auto. split; auto.
  intros x b ty Hin. destruct (E x b ty Hin) as [[]|]; auto.
Qed.

Lemma globalenv_comp: forall p, ge_comp (globalenv p) = prog_types p.
Proof. intros; apply globalenv_props. Qed.

Lemma init_mem_wf: forall p, mem_wf (init_mem p).
Proof. intros; apply globalenv_props. Qed.

(** The block of a global variable holds its zero value at the start. *)
Lemma init_mem_global:
  forall p x b ty, find_var (globalenv p) x = Some (b, ty) ->
  get_block (init_mem p) b = Some (ty, zero_mval (prog_types p) ty)
  /\ (b < mem_next (init_mem p))%positive.
Proof.
  intros p x b ty H. destruct (globalenv_props p) as [[_ [G _]] [C _]].
  rewrite <- C. apply (G x). apply find_assoc_In; auto.
Qed.

(** Different global variables live in different blocks. *)
Lemma globalenv_vars_disjoint:
  forall p x y bx tx by_ ty,
  find_var (globalenv p) x = Some (bx, tx) -> find_var (globalenv p) y = Some (by_, ty) ->
  x <> y -> bx <> by_.
Proof.
  intros p x y bx tx by_ ty Hx Hy N E. subst by_.
  destruct (globalenv_props p) as [[_ [_ ND]] _].
  apply find_assoc_In in Hx; apply find_assoc_In in Hy.
  assert (Inj: forall (l : list (ident * (block * type))) a1 a2,
            NoDup (map (fun xv => fst (snd xv)) l) -> In a1 l -> In a2 l ->
            fst (snd a1) = fst (snd a2) -> a1 = a2).
  { induction l as [|a l IH]; simpl; intros a1 a2 NDl H1 H2 Eq; [contradiction|].
    inversion NDl as [|? ? Ha NDl']; subst.
    destruct H1 as [H1|H1]; destruct H2 as [H2|H2]; subst; auto.
    - exfalso; apply Ha. rewrite Eq. apply (in_map (fun xv => fst (snd xv)) _ _ H2).
    - exfalso; apply Ha. rewrite <- Eq. apply (in_map (fun xv => fst (snd xv)) _ _ H1). }
  assert (Eq := Inj _ _ _ ND Hx Hy eq_refl). inversion Eq; congruence.
Qed.

Lemma var_names_In:
  forall defs x ty, In (x, Gvar ty) defs -> In x (var_names defs).
Proof.
  induction defs as [|[y g] defs IH]; simpl; intros x ty H; [contradiction|].
  destruct H as [H|H]; [inversion H; subst; simpl; auto|].
  apply in_or_app; right; eauto.
Qed.

Lemma fun_defs_In:
  forall defs x fd, In (x, Gfun fd) defs <-> In (x, fd) (fun_defs defs).
Proof.
  induction defs as [|[y g] defs IH]; simpl; intros x fd; [tauto|].
  rewrite in_app_iff, <- IH. destruct g; simpl; split; intros H.
  - destruct H as [H|H]; [inversion H; subst; auto|auto].
  - destruct H as [[H|[]]|H]; [inversion H; subst; auto|auto].
  - destruct H as [H|H]; [discriminate|auto].
  - destruct H as [[]|H]; auto.
Qed.

Lemma NoDup_var_names:
  forall defs, NoDup (map fst defs) -> NoDup (var_names defs).
Proof.
  induction defs as [|[y g] defs IH]; simpl; intros ND; [constructor|].
  inversion ND as [|? ? Hy ND']; subst. destruct g; simpl; auto.
  constructor; auto. intros Hin. apply Hy.
  clear -Hin. induction defs as [|[z h] defs IH]; simpl in *; [contradiction|].
  destruct h; simpl in Hin; [auto|]. destruct Hin; auto.
Qed.

Lemma NoDup_fun_defs:
  forall defs, NoDup (map fst defs) -> NoDup (map fst (fun_defs defs)).
Proof.
  induction defs as [|[y g] defs IH]; simpl; intros ND; [constructor|].
  inversion ND as [|? ? Hy ND']; subst. destruct g; simpl; auto.
  constructor; auto. intros Hin. apply Hy.
  clear -Hin. induction defs as [|[z h] defs IH]; simpl in *; [contradiction|].
  destruct h; simpl in Hin; [|auto]. destruct Hin; auto.
Qed.

Lemma find_def_In:
  forall p x g, NoDup (map fst (prog_defs p)) ->
  (find_def p x = Some g <-> In (x, g) (prog_defs p)).
Proof.
  intros p x g ND; unfold find_def; split.
  - apply find_assoc_In.
  - apply In_find_assoc; auto.
Qed.

(** With distinct names, the global environment finds exactly the
    program's definitions. *)
Lemma find_funct_globalenv:
  forall p x fd, NoDup (map fst (prog_defs p)) ->
  (find_funct (globalenv p) x = Some fd <-> find_def p x = Some (Gfun fd)).
Proof.
  intros p x fd ND. rewrite find_def_In by auto.
  destruct (globalenv_props p) as [_ [_ [_ [F _]]]].
  unfold find_funct; rewrite F, fun_defs_In, in_rev. split.
  - apply find_assoc_In.
  - apply In_find_assoc. rewrite map_rev. apply NoDup_rev, NoDup_fun_defs; auto.
Qed.

Lemma NoDup_fst_In:
  forall (A : Type) (l : list (ident * A)) x a b,
  NoDup (map fst l) -> In (x, a) l -> In (x, b) l -> a = b.
Proof.
  intros A l x a b ND Ha Hb.
  apply (In_find_assoc _ _ _ _ ND) in Ha. apply (In_find_assoc _ _ _ _ ND) in Hb. congruence.
Qed.

Lemma find_var_globalenv:
  forall p x b ty, NoDup (map fst (prog_defs p)) ->
  find_var (globalenv p) x = Some (b, ty) -> find_def p x = Some (Gvar ty).
Proof.
  intros p x b ty ND H. rewrite find_def_In by auto.
  destruct (globalenv_props p) as [_ [_ [_ [_ V]]]].
  apply (V x b). apply find_assoc_In; auto.
Qed.

Lemma globalenv_find_var:
  forall p x ty, NoDup (map fst (prog_defs p)) ->
  find_def p x = Some (Gvar ty) -> exists b, find_var (globalenv p) x = Some (b, ty).
Proof.
  intros p x ty ND H. rewrite find_def_In in H by auto.
  destruct (globalenv_props p) as [_ [_ [N [_ V]]]].
  assert (Hx: In x (map fst (ge_vars (globalenv p)))).
  { rewrite N, <- in_rev. eapply var_names_In; eauto. }
  apply in_map_iff in Hx as [[y [b ty']] [Ey Hin]]. simpl in Ey; subst y.
  assert (Hty: Gvar ty' = Gvar ty) by (eapply NoDup_fst_In; eauto).
  inversion Hty; subst ty'. exists b.
  apply In_find_assoc; auto. rewrite N. apply NoDup_rev, NoDup_var_names; auto.
Qed.

(** ** Determinism *)

(** The semantics is deterministic: a statement, a call or a delivery
    has at most one result.  So the run that [program_behaves] describes
    is *the* run of the program in its environment. *)

Section DETERMINISM.

Context {CS : Type}.
Variable ctx : ros_context CS.
Variable ge : genv.

Local Ltac determ_step :=
  match goal with
  | H : external_call _ _ EF_ros_spinOnce _ _ _ = Some _ |- _ =>
      exfalso; eapply external_call_not_spin; eauto
  | H1 : ?x = Some ?a, H2 : ?x = Some ?b |- _ =>
      rewrite H1 in H2; injection H2; clear H2; intros; subst
  | H1 : ?x = (?a, ?b), H2 : ?x = (?c, ?d) |- _ =>
      rewrite H1 in H2; injection H2; clear H2; intros; subst
  | H1 : typeof ?a = Tfunction _ _, H2 : typeof ?a = Tfunction _ _ |- _ =>
      rewrite H1 in H2; injection H2; clear H2; intros; subst
  | IH : forall t2 le2 m2 w2 out2, exec_stmt ctx ge ?e ?le ?m ?w ?s t2 le2 m2 w2 out2 -> _,
    H : exec_stmt ctx ge ?e ?le ?m ?w ?s _ _ _ _ _ |- _ =>
      let E1 := fresh "E" in let E2 := fresh "E" in let E3 := fresh "E" in
      let E4 := fresh "E" in let E5 := fresh "E" in
      destruct (IH _ _ _ _ _ H) as [E1 [E2 [E3 [E4 E5]]]]; clear IH H;
      try discriminate E5; subst
  | IH : forall t2 m2 w2 v2, eval_funcall ctx ge ?m ?w ?fd ?args t2 m2 w2 v2 -> _,
    H : eval_funcall ctx ge ?m ?w ?fd ?args _ _ _ _ |- _ =>
      let E1 := fresh "E" in let E2 := fresh "E" in let E3 := fresh "E" in
      let E4 := fresh "E" in
      destruct (IH _ _ _ _ H) as [E1 [E2 [E3 E4]]]; clear IH H; subst
  | IH : forall t2 m2 w2, deliver ctx ge ?m ?w ?msgs t2 m2 w2 -> _,
    H : deliver ctx ge ?m ?w ?msgs _ _ _ |- _ =>
      let E1 := fresh "E" in let E2 := fresh "E" in let E3 := fresh "E" in
      destruct (IH _ _ _ H) as [E1 [E2 E3]]; clear IH H; subst
  end.

Theorem semantics_determ:
  (forall e le m w s t1 le1 m1 w1 out1, exec_stmt ctx ge e le m w s t1 le1 m1 w1 out1 ->
     forall t2 le2 m2 w2 out2, exec_stmt ctx ge e le m w s t2 le2 m2 w2 out2 ->
     t1 = t2 /\ le1 = le2 /\ m1 = m2 /\ w1 = w2 /\ out1 = out2)
  /\ (forall m w fd vargs t1 m1 w1 v1, eval_funcall ctx ge m w fd vargs t1 m1 w1 v1 ->
     forall t2 m2 w2 v2, eval_funcall ctx ge m w fd vargs t2 m2 w2 v2 ->
     t1 = t2 /\ m1 = m2 /\ w1 = w2 /\ v1 = v2)
  /\ (forall m w msgs t1 m1 w1, deliver ctx ge m w msgs t1 m1 w1 ->
     forall t2 m2 w2, deliver ctx ge m w msgs t2 m2 w2 ->
     t1 = t2 /\ m1 = m2 /\ w1 = w2).
Proof.
  apply exec_stmt_funcall_deliver_ind;
    intros;
    (* keep only the second derivation; the first ones are summarised by
       their induction hypotheses *)
    match goal with H : _ |- _ => revert H end;
    repeat match goal with
    | H : exec_stmt _ _ _ _ _ _ _ _ _ _ _ _ |- _ => clear H
    | H : eval_funcall _ _ _ _ _ _ _ _ _ _ |- _ => clear H
    | H : deliver _ _ _ _ _ _ _ _ |- _ => clear H
    end;
    let H2 := fresh "H" in intro H2; inversion H2; subst;
    repeat determ_step;
    try congruence;
    repeat split; auto; congruence.
Qed.

End DETERMINISM.

(** A program has at most one behaviour in a given environment. *)
Corollary program_behaves_determ:
  forall (CS : Type) p (ctx : ros_context CS) n t1 t2,
  program_behaves p ctx n t1 -> program_behaves p ctx n t2 -> t1 = t2.
Proof.
  intros CS p ctx n t1 t2 [fd1 m1 w1 v1 F1 E1] [fd2 m2 w2 v2 F2 E2].
  rewrite F1 in F2; inversion F2; subst fd2.
  destruct (semantics_determ ctx (globalenv p)) as [_ [D _]].
  destruct (D _ _ _ _ _ _ _ _ E1 _ _ _ _ E2) as [T _]. exact T.
Qed.
