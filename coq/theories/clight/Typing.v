(** * Typing of the Clight subset *)

(** [wt_program p]: the static conditions that the generator establishes
    for its output, as an inductive specification, and its decision
    procedure [check_program] ([check_program_correct]).  The semantics
    ([Semantics]) does not depend on typing: an ill-typed construct is
    simply stuck there. *)

From Coq Require Import String List ZArith Bool Lia.
From ROSGen Require Import Syntax Values Operators Memory.
Import ListNotations.
Local Open Scope Z_scope.

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
      wt_expr (Ecast a ty)
  | wt_Eunop: forall op a ty,
      wt_expr a -> unop_type op (typeof a) = Some ty ->
      wt_expr (Eunop op a ty)
  | wt_Ebinop: forall op a1 a2 ty,
      wt_expr a1 -> wt_expr a2 -> typeof a1 = typeof a2 ->
      binop_type op (typeof a1) = Some ty ->
      wt_expr (Ebinop op a1 a2 ty).

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
  | Eunop op a1 ty =>
      check_expr a1 &&
      match unop_type op (typeof a1) with
      | Some ty' => type_eqb ty' ty
      | None => false
      end
  | Ebinop op a1 a2 ty =>
      check_expr a1 && check_expr a2 && type_eqb (typeof a1) (typeof a2) &&
      match binop_type op (typeof a1) with
      | Some ty' => type_eqb ty' ty
      | None => false
      end
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
                 | a1 IH1 f ty | a1 IH1 i IHi ty | a1 IH1 ty
                 | op a1 IH1 ty | op a1 IH1 a2 IH2 ty]; simpl; intros H.
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
  - split_andb. destruct (unop_type op (typeof a1)) as [ty'|] eqn:U; try discriminate.
    split_andb. constructor; auto.
  - split_andb. destruct (binop_type op (typeof a1)) as [ty'|] eqn:U; try discriminate.
    split_andb. constructor; auto.
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
  | EF_ros_init | EF_ros_spinOnce | EF_ros_rate_sleep _ => ([], Tvoid)
  | EF_ros_ok => ([], tint)
  | EF_ros_now => ([], Tlong Unsigned)
  | EF_ros_time_sec | EF_ros_time_nsec => ([], Tint I32 Unsigned)
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

