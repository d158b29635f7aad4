(** * Big-step semantics of the Clight subset, with the ROS environment model *)

(** This file gives the meaning of the programs of [Syntax]:
    - expressions are evaluated by *functions* ([eval_expr],
      [eval_lvalue]): expressions of the subset have no side effects, so
      their evaluation is deterministic; the relational reading is
      [eval_expr ... a = Some v]; the arithmetic operators mean what
      [Operators] says, and an operation whose operand or result types are
      not the ones [Operators.unop_type] / [binop_type] allow is stuck
      (so the semantics never performs an implicit conversion);
    - statements, function calls and the delivery of messages by
      [ros_spinOnce] are big-step judgements ([exec_stmt], [eval_funcall],
      [deliver]), mutually inductive because [ros_spinOnce] runs the
      callbacks, which are functions of the program;
    - external functions (the ROS C API and the controller interface) get
      their meaning from the environment model of [Environment]
      ([external_call], [spin_messages]);
    - [program_behaves p ctx n t]: [main] runs to completion with trace [t]
      when [ros_ok] answers true [n] times.

    The environment model (the meaning of the external functions, the
    message queues, the events) is in [Environment]; the typing rules of
    the subset are in [Typing]. *)

From Coq Require Import String List ZArith Bool Lia.
From ROSGen Require Import Syntax Values Operators Memory Environment.
Import ListNotations.
Local Open Scope Z_scope.

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

(** ** Local environments *)

(** Local environment: block and type of each addressable local. *)
Definition env := list (ident * (block * type)).

(** Temporaries (parameters included): their current values. *)
Definition temp_env := list (ident * val).

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
  | Eunop op a1 ty =>
      match unop_type op (typeof a1), eval_expr a1 with
      | Some ty', Some v => if type_eqb ty ty' then sem_unop op (typeof a1) v else None
      | _, _ => None
      end
  | Ebinop op a1 a2 ty =>
      match binop_type op (typeof a1), eval_expr a1, eval_expr a2 with
      | Some ty', Some v1, Some v2 =>
          if type_eqb (typeof a1) (typeof a2) && type_eqb ty ty'
          then sem_binop op (typeof a1) v1 v2 else None
      | _, _, _ => None
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
  intros a H; destruct a as [| | | | x ty | | | | | | | |]; try contradiction; auto.
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

(** [exec_stmt e le m w s t le' m' w' out]: statement [s], started with
    locals [e], temporaries [le], memory [m] and world [w], terminates
    with events [t], temporaries [le'], memory [m'], world [w'], ending
    as [out].

    [eval_funcall m w fd args t m' w' v]: calling [fd] with [args]
    terminates with events [t] and returns [v].

    [deliver m w msgs t m' w']: running the callbacks of [msgs] in order
    (skipping the messages not [accepted]: policy "reject"),
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
      external_call ctx ge ef vargs m w = Some (vres, t, m', w') ->
      eval_funcall m w (External ef targs tres) vargs t m' w' vres
  | eval_funcall_spinOnce: forall targs tres m w t m' w',
      deliver m w (spin_messages ctx w) t m' w' ->
      eval_funcall m w (External EF_ros_spinOnce targs tres) [] t m' (next_spin ctx w') Vundef

with deliver : mem -> world CS -> list (subscription * arrival) ->
               trace -> mem -> world CS -> Prop :=
  | deliver_nil: forall m w,
      deliver m w [] [] m w
  | deliver_cons: forall m w s a rest m1 b fd t1 m2 w1 v t2 m3 w2,
      accepted ge s a = true ->
      alloc m (Tstruct (sub_msgty s)) (delivered ge s a) = (m1, b) ->
      find_funct ge (sub_callback s) = Some fd ->
      eval_funcall m1 (set_time w (ar_time a)) fd [Vptr b []] t1 m2 w1 v ->
      deliver (free m2 b) w1 rest t2 m3 w2 ->
      deliver m w ((s, a) :: rest) (t1 ++ t2) m3 w2
  | deliver_rejected: forall m w s a rest t m' w',
      accepted ge s a = false ->
      deliver m w rest t m' w' ->
      deliver m w ((s, a) :: rest) t m' w'.

Scheme exec_stmt_ind3 := Minimality for exec_stmt Sort Prop
  with eval_funcall_ind3 := Minimality for eval_funcall Sort Prop
  with deliver_ind3 := Minimality for deliver Sort Prop.
Combined Scheme exec_stmt_funcall_deliver_ind from exec_stmt_ind3, eval_funcall_ind3, deliver_ind3.

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
Theorem program_behaves_determ:
  forall (CS : Type) p (ctx : ros_context CS) n t1 t2,
  program_behaves p ctx n t1 -> program_behaves p ctx n t2 -> t1 = t2.
Proof.
  intros CS p ctx n t1 t2 [fd1 m1 w1 v1 F1 E1] [fd2 m2 w2 v2 F2 E2].
  rewrite F1 in F2; inversion F2; subst fd2.
  destruct (semantics_determ ctx (globalenv p)) as [_ [D _]].
  destruct (D _ _ _ _ _ _ _ _ E1 _ _ _ _ E2) as [T _]. exact T.
Qed.
