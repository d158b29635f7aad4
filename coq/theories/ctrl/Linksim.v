(** * Simulation of a program by its linked version, for any program *)

(** The generic part of T8 ([Link]): a program [p] run in an environment
    whose controller is some model, and a program [pL] in which the
    blocks of [p] are renamed ([rb]: injective, monotone), whose
    functions are [p]'s except the controller's ([lfd]), and whose
    memory holds one more block (the controller's state) and one more
    struct.  Renaming of values, memories and environments ([rv], [rmv],
    [mrel], [grel]), evaluation under renaming, function entry and exit,
    traces with the controller's events erased ([rtrace]); the forward
    simulation [sim] (any controller implementation related to the
    environment's by [crel]); one more struct ([EXTEND]: conversions and
    default values unchanged); the allocation of the globals of the
    linked program ([alloc_globals_link]).  [Link] instantiates it with
    the generated glue and the controller generated from a diagram. *)
From Coq Require Import String List ZArith Bool Lia.
From ROSGen Require Import Maps Errors Syntax Values Operators Memory Environment Semantics.
From ROSGen Require Loopproof.
Import ListNotations.

(** ** Renaming blocks *)

Section RENAME.

Variable rb : block -> block.
Hypothesis rb_inj : forall b1 b2, rb b1 = rb b2 -> b1 = b2.
Hypothesis rb_succ : forall b, rb (Pos.succ b) = Pos.succ (rb b).

Definition rv (v : val) : val :=
  match v with
  | Vptr b p => Vptr (rb b) p
  | _ => v
  end.

Fixpoint rmv (mv : mval) : mval :=
  match mv with
  | MVscalar v => MVscalar (rv v)
  | MVstruct fs =>
      MVstruct ((fix go (l : list (ident * mval)) : list (ident * mval) :=
                   match l with
                   | [] => []
                   | (f, x) :: l' => (f, rmv x) :: go l'
                   end) fs)
  | MVarray es =>
      MVarray ((fix go (l : list mval) : list mval :=
                  match l with
                  | [] => []
                  | x :: l' => rmv x :: go l'
                  end) es)
  end.

Definition rfs (fs : list (ident * mval)) : list (ident * mval) :=
  map (fun fx => (fst fx, rmv (snd fx))) fs.

Lemma rmv_struct: forall fs, rmv (MVstruct fs) = MVstruct (rfs fs).
Proof.
  intros fs. simpl. f_equal. induction fs as [|[f x] fs IH]; simpl; auto; unfold rfs in *; simpl; rewrite <- IH; reflexivity.
Qed.

Lemma rmv_array: forall es, rmv (MVarray es) = MVarray (map rmv es).
Proof.
  intros es. simpl. try (f_equal; induction es as [|x es IH]; simpl; auto; rewrite <- IH; reflexivity).
Qed.

Lemma rmv_scalar: forall v, rmv (MVscalar v) = MVscalar (rv v).
Proof. reflexivity. Qed.

Arguments rmv : simpl never.

Lemma find_assoc_rfs: forall f fs, find_assoc f (rfs fs) = option_map rmv (find_assoc f fs).
Proof.
  induction fs as [|[g x] fs IH]; simpl; auto. destruct (string_dec f g); auto.
Qed.

Lemma nth_error_map_rmv: forall es n, nth_error (map rmv es) n = option_map rmv (nth_error es n).
Proof. induction es as [|x es IH]; intros [|n]; simpl; auto. Qed.

Lemma get_step_rmv: forall mv s, get_step (rmv mv) s = option_map rmv (get_step mv s).
Proof.
  intros [v|fs|es] [f|i]; try rewrite rmv_struct; try rewrite rmv_array; simpl; try reflexivity.
  - apply find_assoc_rfs.
  - destruct (0 <=? i)%Z; auto. apply nth_error_map_rmv.
Qed.

Lemma set_field_rfs: forall f x fs, set_field f (rmv x) (rfs fs) = rfs (set_field f x fs).
Proof.
  induction fs as [|[g y] fs IH]; simpl; auto. destruct (ident_eq f g); simpl; auto. rewrite IH; auto.
Qed.

Lemma replace_nth_map_rmv: forall es n x, replace_nth (map rmv es) n (rmv x) = map rmv (replace_nth es n x).
Proof. induction es as [|y es IH]; intros [|n] x; simpl; auto. rewrite IH; auto. Qed.

Lemma set_step_rmv: forall mv s x, set_step (rmv mv) s (rmv x) = option_map rmv (set_step mv s x).
Proof.
  intros [v|fs|es] [f|i] x; try rewrite rmv_struct; try rewrite rmv_array; simpl; try reflexivity.
  - rewrite find_assoc_rfs. destruct (find_assoc f fs); simpl; auto.
    rewrite set_field_rfs. rewrite rmv_struct. auto.
  - rewrite map_length.
    destruct ((0 <=? i)%Z && Nat.ltb (Z.to_nat i) (length es)); simpl; auto.
    rewrite replace_nth_map_rmv, rmv_array. auto.
Qed.

Lemma mval_get_rmv: forall p mv, mval_get (rmv mv) p = option_map rmv (mval_get mv p).
Proof.
  induction p as [|s p IH]; intros mv; simpl; auto.
  rewrite get_step_rmv. destruct (get_step mv s); simpl; auto.
Qed.

Lemma mval_set_rmv: forall p mv v, mval_set (rmv mv) p (rmv v) = option_map rmv (mval_set mv p v).
Proof.
  induction p as [|s p IH]; intros mv v; simpl; auto.
  rewrite get_step_rmv. destruct (get_step mv s) as [x|]; simpl; auto.
  rewrite IH. destruct (mval_set x p v) as [x'|]; simpl; auto. apply set_step_rmv.
Qed.

Lemma sem_cast_rv: forall v ty, sem_cast (rv v) ty = option_map rv (sem_cast v ty).
Proof.
  intros v ty; destruct ty as [| sz sg | sg | [|] | t | t len | args r | id ];
    destruct v as [| n | n | f | f | b p | fid]; simpl; auto; destruct n; auto.
Qed.

Lemma bool_val_rv: forall v, bool_val (rv v) = bool_val v.
Proof. intros [| | | | |b p|]; reflexivity. Qed.

Lemma val_has_typeb_rv: forall v ty, val_has_typeb (rv v) ty = val_has_typeb v ty.
Proof. intros v ty; destruct ty, v; reflexivity. Qed.

Lemma rv_typed:
  forall r ty, val_has_type r ty -> (forall t, ty <> Tpointer t) -> rv r = r.
Proof.
  intros r ty H N. destruct r; auto. destruct ty as [| | |[|]| | | |]; simpl in H; try contradiction. exfalso; eapply N; reflexivity.
Qed.

Lemma unop_type_not_ptr: forall op ty ty' t, unop_type op ty = Some ty' -> ty' <> Tpointer t.
Proof.
  intros op ty ty' t H E; subst. unfold unop_type in H.
  destruct op, ty; try discriminate;
    repeat match type of H with
    | (match ?x with _ => _ end) = _ => destruct x
    | (if ?x then _ else _) = _ => destruct x end; try discriminate; inversion H; subst; discriminate.
Qed.

Lemma binop_type_not_ptr: forall op ty ty' t, binop_type op ty = Some ty' -> ty' <> Tpointer t.
Proof.
  intros op ty ty' t H E; subst. unfold binop_type in H.
  destruct (arith_type ty) eqn:A; [|discriminate].
  destruct (is_comparison op); [discriminate|].
  destruct op, ty; try discriminate; try (inversion H; subst; discriminate A);
    repeat match type of H with
    | (match ?x with _ => _ end) = _ => destruct x
    | (if ?x then _ else _) = _ => destruct x end; try discriminate;
    inversion H; subst; discriminate A.
Qed.

Lemma sem_unop_rv:
  forall op ty ty' v r, unop_type op ty = Some ty' -> sem_unop op ty v = Some r ->
  sem_unop op ty (rv v) = Some (rv r).
Proof.
  intros op ty ty' v r T H.
  rewrite (rv_typed r ty' (sem_unop_type op ty v r ty' H T) (fun t => unop_type_not_ptr op ty ty' t T)).
  destruct v; try exact H;
  unfold unop_type in T; destruct op, ty as [| sz sg | sg | [|] | t | t len | args res | id ];
    try destruct sz; try discriminate; simpl in H; discriminate.
Qed.

Lemma sem_binop_rv:
  forall op ty ty' v1 v2 r, binop_type op ty = Some ty' -> sem_binop op ty v1 v2 = Some r ->
  sem_binop op ty (rv v1) (rv v2) = Some (rv r).
Proof.
  intros op ty ty' v1 v2 r T H.
  rewrite (rv_typed r ty' (sem_binop_type op ty v1 v2 r ty' H T) (fun t => binop_type_not_ptr op ty ty' t T)).
  destruct v1, v2; try exact H;
  destruct ty as [| sz sg | sg | [|] | t | t len | args res | id ]; try destruct sz; discriminate.
Qed.

(** *** Memories *)

Definition rblk (tv : type * mval) : type * mval := (fst tv, rmv (snd tv)).

(** [mL] holds, at block [rb b], the renamed contents of block [b] of [m];
    other blocks of [mL] (the controller's state) are not constrained. *)
Record mrel (m mL : mem) : Prop := {
  mr_next : mem_next mL = rb (mem_next m);
  mr_get : forall b, get_block mL (rb b) = option_map rblk (get_block m b)
}.

(** A block that is not the renaming of any block. *)
Definition extra (x : block) : Prop := forall b, x <> rb b.

(** [mL'] agrees with [mL] on the extra blocks. *)
Definition same_extra (mL mL' : mem) : Prop := forall x, extra x -> get_block mL' x = get_block mL x.

Lemma same_extra_refl: forall mL, same_extra mL mL.
Proof. intros mL x _; auto. Qed.

Lemma same_extra_trans: forall a b c, same_extra a b -> same_extra b c -> same_extra a c.
Proof. intros a b c H1 H2 x X. rewrite H2, H1; auto. Qed.

Lemma load_path_rel:
  forall m mL b p mv, mrel m mL -> load_path m b p = Some mv -> load_path mL (rb b) p = Some (rmv mv).
Proof.
  intros m mL b p mv R H. unfold load_path in *. rewrite (mr_get _ _ R).
  destruct (get_block m b) as [[ty v]|]; [|discriminate]. simpl. rewrite mval_get_rmv, H. reflexivity.
Qed.

Lemma load_rel:
  forall ty m mL b p v, mrel m mL -> load ty m b p = Some v -> load ty mL (rb b) p = Some (rv v).
Proof.
  intros ty m mL b p v R H. unfold load in *. destruct (is_scalar_type ty); [|discriminate].
  destruct (load_path m b p) as [mv|] eqn:L; [|discriminate].
  rewrite (load_path_rel _ _ _ _ _ R L). destruct mv; try discriminate. inversion H; subst. reflexivity.
Qed.

Lemma store_path_rel:
  forall m mL b p v m', mrel m mL -> store_path m b p v = Some m' ->
  exists mL', store_path mL (rb b) p (rmv v) = Some mL' /\ mrel m' mL' /\ same_extra mL mL'.
Proof.
  intros m mL b p v m' R H. unfold store_path in *.
  generalize (mr_get _ _ R b). intros G. destruct (get_block m b) as [[ty mv]|] eqn:Gb; [|discriminate].
  rewrite G. cbn [option_map rblk fst snd]. rewrite mval_set_rmv.
  destruct (mval_set mv p v) as [mv'|] eqn:S; [|discriminate]. simpl. inversion H; subst. clear H.
  eexists; split; [reflexivity|]. split; [split|].
  - simpl. apply (mr_next _ _ R).
  - intros b'. unfold get_block; simpl. destruct (Pos.eq_dec b' b) as [->|N].
    + rewrite !pgss. reflexivity.
    + rewrite !pgso; try (apply (mr_get _ _ R)); try (intros E; apply N, rb_inj; now auto); auto.
  - intros x X. unfold get_block; simpl. rewrite pgso; auto.
Qed.

Lemma store_rel:
  forall ty m mL b p v m', mrel m mL -> store ty m b p v = Some m' ->
  exists mL', store ty mL (rb b) p (rv v) = Some mL' /\ mrel m' mL' /\ same_extra mL mL'.
Proof.
  intros ty m mL b p v m' R H. unfold store in *. rewrite sem_cast_rv.
  destruct (sem_cast v ty) as [v'|]; [|discriminate]. simpl.
  apply (store_path_rel _ _ _ _ (MVscalar v') _ R H).
Qed.

Lemma alloc_rel:
  forall m mL ty mv m' b, mrel m mL -> alloc m ty mv = (m', b) ->
  exists mL', alloc mL ty (rmv mv) = (mL', rb b) /\ mrel m' mL' /\ same_extra mL mL'.
Proof.
  intros m mL ty mv m' b R H. unfold alloc in *. inversion H; subst. clear H.
  rewrite (mr_next _ _ R). eexists; split; [reflexivity|]. split; [split|].
  - simpl. rewrite rb_succ. reflexivity.
  - intros b'. unfold get_block; simpl. destruct (Pos.eq_dec b' (mem_next m)) as [->|N].
    + rewrite !pgss. reflexivity.
    + rewrite !pgso; try (apply (mr_get _ _ R)); try (intros E; apply N, rb_inj; now auto); auto.
  - intros x X. unfold get_block; simpl. rewrite pgso; auto.
Qed.

Lemma free_rel:
  forall m mL b, mrel m mL -> mrel (free m b) (free mL (rb b)) /\ same_extra mL (free mL (rb b)).
Proof.
  intros m mL b R. split; [split|].
  - simpl. apply (mr_next _ _ R).
  - intros b'. unfold get_block; simpl. destruct (Pos.eq_dec b' b) as [->|N].
    + rewrite !pgrs. reflexivity.
    + rewrite !pgro; try (apply (mr_get _ _ R)); try (intros E; apply N, rb_inj; now auto); auto.
  - intros x X. unfold get_block; simpl. rewrite pgro; auto.
Qed.

(** *** Values without pointers *)

Lemma rmv_default_of:
  forall dflt zs, (forall t, rv (dflt t) = dflt t) -> (forall id, rmv (zs id) = zs id) ->
  forall ty, rmv (default_of dflt zs ty) = default_of dflt zs ty.
Proof.
  intros dflt zs D Z. induction ty as [| sz sg | sg | fs | t IHt | t IHt n | args r | id]; simpl; auto;
    try (rewrite rmv_scalar, D; reflexivity).
  rewrite rmv_array. f_equal. generalize (Z.to_nat n). intros k. induction k; simpl; auto. rewrite IHt, IHk; auto.
Qed.

Lemma rmv_struct_default:
  forall dflt, (forall t, rv (dflt t) = dflt t) ->
  forall rce id, rmv (struct_default dflt rce id) = struct_default dflt rce id.
Proof.
  intros dflt D. induction rce as [|co rce IH]; intros id; simpl; auto.
  destruct (ident_eq (co_name co) id); auto.
  rewrite rmv_struct. f_equal. unfold rfs. rewrite map_map. simpl.
  apply map_ext. intros [f t]. simpl. rewrite rmv_default_of; auto.
Qed.

Lemma rmv_default_mval:
  forall dflt ce ty, (forall t, rv (dflt t) = dflt t) -> rmv (default_mval dflt ce ty) = default_mval dflt ce ty.
Proof.
  intros dflt ce ty D. unfold default_mval. apply rmv_default_of; auto. apply rmv_struct_default; auto.
Qed.

Lemma rv_zero_val: forall t, rv (zero_val t) = zero_val t.
Proof. intros t; destruct t as [| | |[|]| | | |]; reflexivity. Qed.

Lemma rmv_zero: forall ce ty, rmv (zero_mval ce ty) = zero_mval ce ty.
Proof. intros; apply rmv_default_mval, rv_zero_val. Qed.

Lemma rmv_undef: forall ce ty, rmv (undef_mval ce ty) = undef_mval ce ty.
Proof. intros; apply rmv_default_mval; reflexivity. Qed.

(** *** The conversions of received and published messages *)

Lemma map_repeat_rmv: forall x n, map rmv (repeat x n) = repeat (rmv x) n.
Proof. induction n; simpl; auto. rewrite IHn; auto. Qed.

Lemma clamp_seq_rmv:
  forall ce members fs, clamp_seq ce members (rfs fs) = option_map rmv (clamp_seq ce members fs).
Proof.
  intros ce members fs.
  destruct fs as [|[fl x1] [|[ft x2] [|[fd x3] fs']]]; unfold rfs; simpl map;
    try (destruct x1 as [v1|?|?]; [rewrite rmv_scalar; destruct v1|rewrite rmv_struct|rewrite rmv_array]);
    try (destruct x3 as [v3|?|?]; [rewrite rmv_scalar|rewrite rmv_struct|rewrite rmv_array]);
    unfold clamp_seq; simpl rv;
    repeat match goal with |- context [match ?x with _ => _ end] => is_var x; destruct x end;
    try reflexivity.
  all: simpl option_map; f_equal;
    rewrite rmv_struct; unfold rfs; simpl map; rewrite !rmv_scalar, rmv_array; simpl rv;
    rewrite map_app, firstn_map, map_repeat_rmv, map_length, rmv_zero; reflexivity.
Qed.

Lemma clamp_fields_rmv:
  forall ce fs, Forall (fun fv => forall ty, clamp ce ty (rmv (snd fv)) = rmv (clamp ce ty (snd fv))) fs ->
  forall members, clamp_fields ce members (rfs fs) = rfs (clamp_fields ce members fs).
Proof.
  intros ce fs IH. induction IH as [|[g v] fs Hv IHfs IHrec]; intros members; [destruct members as [|[? ?] ?]; reflexivity|].
  destruct members as [|[f t] ms]; [reflexivity|]. simpl in Hv |- *. rewrite Hv, IHrec. reflexivity.
Qed.

Lemma clamp_rmv: forall ce mv ty, clamp ce ty (rmv mv) = rmv (clamp ce ty mv).
Proof.
  intros ce mv. induction mv as [v | fs IH | es IH] using mval_ind2; intros ty.
  - reflexivity.
  - rewrite rmv_struct. destruct ty; try (simpl; rewrite rmv_struct; reflexivity).
    rewrite !clamp_struct_eq. destruct (struct_members ce id) as [members|]; [|rewrite rmv_struct; reflexivity].
    rewrite (clamp_fields_rmv ce fs IH members).
    destruct (bounded_name id).
    + rewrite clamp_seq_rmv. destruct (clamp_seq ce members (clamp_fields ce members fs)); [reflexivity|].
      simpl. rewrite rmv_struct. reflexivity.
    + rewrite rmv_struct. reflexivity.
  - rewrite rmv_array. destruct ty; simpl; try (rewrite rmv_array; reflexivity).
    rewrite rmv_array. f_equal. rewrite !map_map. apply map_ext_in. intros x Hx.
    rewrite Forall_forall in IH. apply IH; auto.
Qed.

Lemma too_long_rmv: forall ce mv ty, too_long ce ty (rmv mv) = too_long ce ty mv.
Proof.
  intros ce mv. induction mv as [v | fs IH | es IH] using mval_ind2; intros ty.
  - reflexivity.
  - rewrite rmv_struct. destruct ty; simpl; try reflexivity.
    destruct (struct_members ce id) as [members|]; [|reflexivity].
    f_equal.
    + f_equal. unfold seq_too_long.
      destruct fs as [|[f x] fs]; [reflexivity|]. unfold rfs; simpl map.
      destruct x as [v|fs1|es1]; [rewrite rmv_scalar|rewrite rmv_struct|rewrite rmv_array];
        [destruct v|..]; simpl rv;
        destruct members as [|[a1 t1] [|[a2 t2] [|[a3 t3] [|]]]]; try reflexivity; destruct t3; reflexivity.
    + revert members. induction IH as [|[g v] fs Hv IHfs IHrec]; intros members.
      * destruct members as [|[? ?] ?]; reflexivity.
      * destruct members as [|[f t] ms]; [reflexivity|]. simpl in Hv |- *. rewrite Hv, IHrec. reflexivity.
  - rewrite rmv_array. destruct ty; simpl; try reflexivity.
    induction IH as [|x es Hx IHes IHrec]; simpl; auto. rewrite Hx, IHrec. reflexivity.
Qed.

(** *** Expressions *)

Definition re (e : env) : env := map (fun xb => (fst xb, (rb (fst (snd xb)), snd (snd xb)))) e.
Definition rle (le : temp_env) : temp_env := map (fun xv => (fst xv, rv (snd xv))) le.

Lemma find_assoc_re:
  forall x e, find_assoc x (re e) = option_map (fun bt => (rb (fst bt), snd bt)) (find_assoc x e).
Proof. induction e as [|[y [b t]] e IH]; simpl; auto. destruct (string_dec x y); auto. Qed.

Lemma find_assoc_rle: forall x le, find_assoc x (rle le) = option_map rv (find_assoc x le).
Proof. induction le as [|[y v] le IH]; simpl; auto. destruct (string_dec x y); auto. Qed.

Lemma set_assoc_rle: forall x v le, set_assoc x (rv v) (rle le) = rle (set_assoc x v le).
Proof. induction le as [|[y w] le IH]; simpl; auto. destruct (ident_eq x y); simpl; auto. rewrite IH; auto. Qed.

Lemma set_assoc_re:
  forall x b t e, set_assoc x (rb b, t) (re e) = re (set_assoc x (b, t) e).
Proof. induction e as [|[y [b' t']] e IH]; simpl; auto. destruct (ident_eq x y); simpl; auto. rewrite IH; auto. Qed.

(** The glue's global environment [ge] and the linked program's [geL]. *)
Variable lfd : fundef -> fundef.

Record grel (ge geL : genv) : Prop := {
  gr_var : forall x b ty, find_var ge x = Some (b, ty) -> find_var geL x = Some (rb b, ty);
  gr_novar : forall x fd, find_var ge x = None -> find_funct ge x = Some fd -> find_var geL x = None;
  gr_funct : forall x fd, find_funct ge x = Some fd -> find_funct geL x = Some (lfd fd)
}.

Lemma ev_lderef: forall ge e le m a ty, eval_lvalue ge e le m (Ederef a ty) = lvalue_deref (eval_expr ge e le m a).
Proof. reflexivity. Qed.
Lemma ev_lfield: forall ge e le m a f ty, eval_lvalue ge e le m (Efield a f ty) = lvalue_field a (eval_lvalue ge e le m a) f.
Proof. reflexivity. Qed.
Lemma ev_lindex: forall ge e le m a i ty,
  eval_lvalue ge e le m (Eindex a i ty) = lvalue_index a (eval_lvalue ge e le m a) (eval_expr ge e le m i).
Proof. reflexivity. Qed.
Lemma ev_deref: forall ge e le m a ty, eval_expr ge e le m (Ederef a ty) = load_loc m ty (lvalue_deref (eval_expr ge e le m a)).
Proof. reflexivity. Qed.
Lemma ev_field: forall ge e le m a f ty,
  eval_expr ge e le m (Efield a f ty) = load_loc m ty (lvalue_field a (eval_lvalue ge e le m a) f).
Proof. reflexivity. Qed.
Lemma ev_index: forall ge e le m a i ty,
  eval_expr ge e le m (Eindex a i ty) = load_loc m ty (lvalue_index a (eval_lvalue ge e le m a) (eval_expr ge e le m i)).
Proof. reflexivity. Qed.
Lemma ev_addrof: forall ge e le m a ty,
  eval_expr ge e le m (Eaddrof a ty)
  = match a with
    | Evar x (Tfunction _ _) => eval_funcname ge e x
    | _ => match eval_lvalue ge e le m a with Some (b, p) => Some (Vptr b p) | None => None end
    end.
Proof. intros. destruct a; try destruct ty0; reflexivity. Qed.
Lemma ev_cast: forall ge e le m a ty,
  eval_expr ge e le m (Ecast a ty) = match eval_expr ge e le m a with Some v => sem_cast v ty | None => None end.
Proof. reflexivity. Qed.
Lemma ev_unop: forall ge e le m op a ty,
  eval_expr ge e le m (Eunop op a ty)
  = match unop_type op (typeof a), eval_expr ge e le m a with
    | Some ty', Some v => if type_eqb ty ty' then sem_unop op (typeof a) v else None
    | _, _ => None
    end.
Proof. reflexivity. Qed.
Lemma ev_binop: forall ge e le m op a1 a2 ty,
  eval_expr ge e le m (Ebinop op a1 a2 ty)
  = match binop_type op (typeof a1), eval_expr ge e le m a1, eval_expr ge e le m a2 with
    | Some ty', Some v1, Some v2 =>
        if type_eqb (typeof a1) (typeof a2) && type_eqb ty ty' then sem_binop op (typeof a1) v1 v2 else None
    | _, _, _ => None
    end.
Proof. reflexivity. Qed.

Section EVAL.

Variables (ge geL : genv) (e : env) (le : temp_env) (m mL : mem).
Hypothesis G : grel ge geL.
Hypothesis R : mrel m mL.

Lemma lvalue_var_rel:
  forall x b p, lvalue_var ge e x = Some (b, p) -> lvalue_var geL (re e) x = Some (rb b, p).
Proof.
  intros x b p H. unfold lvalue_var in *. rewrite find_assoc_re.
  destruct (find_assoc x e) as [[b' t']|]; simpl.
  - inversion H; subst; reflexivity.
  - destruct (find_var ge x) as [[b' t']|] eqn:V; [|discriminate]. inversion H; subst.
    rewrite (gr_var _ _ G _ _ _ V). reflexivity.
Qed.

Lemma eval_funcname_rel:
  forall x v, eval_funcname ge e x = Some v -> eval_funcname geL (re e) x = Some (rv v).
Proof.
  intros x v H. unfold eval_funcname in *. rewrite find_assoc_re.
  destruct (find_assoc x e); [discriminate|].
  destruct (find_var ge x) eqn:V; [discriminate|].
  destruct (find_funct ge x) as [fd|] eqn:F; [|discriminate]. inversion H; subst.
  simpl. rewrite (gr_novar _ _ G _ _ V F), (gr_funct _ _ G _ _ F). reflexivity.
Qed.

Lemma load_loc_rel:
  forall ty b p v, load_loc m ty (Some (b, p)) = Some v -> load_loc mL ty (Some (rb b, p)) = Some (rv v).
Proof. intros ty b p v H. simpl in *. apply (load_rel _ _ _ _ _ _ R H). Qed.

Lemma eval_rel:
  forall a,
     (forall v, eval_expr ge e le m a = Some v -> eval_expr geL (re e) (rle le) mL a = Some (rv v))
  /\ (forall b p, eval_lvalue ge e le m a = Some (b, p) -> eval_lvalue geL (re e) (rle le) mL a = Some (rb b, p)).
Proof.
  induction a as [n ty|n ty|f ty|f ty|x ty|x ty|a1 IH1 ty|a1 IH1 ty|a1 IH1 f ty|a1 IH1 i IHi ty|a1 IH1 ty
                  |op a1 IH1 ty|op a1 IH1 a2 IH2 ty]; split; intros;
    try (simpl in H; discriminate).
  - destruct ty; try destruct i; try destruct s; simpl in *; try discriminate; inversion H; subst; reflexivity.
  - destruct ty; simpl in *; try discriminate; inversion H; subst; reflexivity.
  - destruct ty as [| | |[|]| | | |]; simpl in *; try discriminate; inversion H; subst; reflexivity.
  - destruct ty as [| | |[|]| | | |]; simpl in *; try discriminate; inversion H; subst; reflexivity.
  - destruct ty; cbn [eval_expr] in *;
      try (unfold load_loc in *; destruct (lvalue_var ge e x) as [[b p]|] eqn:L; [|discriminate];
           rewrite (lvalue_var_rel _ _ _ L); apply (load_rel _ _ _ _ _ _ R H)).
    apply eval_funcname_rel; auto.
  - destruct ty; cbn [eval_expr eval_lvalue] in *; try discriminate; apply lvalue_var_rel; auto.
  - cbn [eval_expr eval_lvalue] in *. rewrite find_assoc_rle, H. reflexivity.
  - rewrite ev_deref in *. unfold lvalue_deref, load_loc in *.
    destruct (eval_expr ge e le m a1) as [v1|] eqn:E1; [|discriminate].
    destruct v1; try discriminate. rewrite (proj1 IH1 _ eq_refl). apply (load_rel _ _ _ _ _ _ R H).
  - rewrite ev_lderef in *. unfold lvalue_deref, load_loc in *.
    destruct (eval_expr ge e le m a1) as [v1|] eqn:E1; [|discriminate].
    destruct v1; try discriminate. inversion H; subst. rewrite (proj1 IH1 _ eq_refl). reflexivity.
  - rewrite ev_addrof in *. destruct a1 as [| | | |x0 [| | | | | | |]| | | | | | | |];
      try (destruct (eval_lvalue ge e le m _) as [[b p]|] eqn:L; [|discriminate];
           inversion H; subst; rewrite (proj2 IH1 _ _ eq_refl); reflexivity).
    apply eval_funcname_rel; auto.
  - rewrite ev_field in *. unfold lvalue_field, load_loc in *. destruct (typeof a1); try discriminate.
    destruct (eval_lvalue ge e le m a1) as [[b0 p0]|] eqn:L; [|discriminate].
    rewrite (proj2 IH1 _ _ eq_refl). apply (load_rel _ _ _ _ _ _ R H).
  - rewrite ev_lfield in *. unfold lvalue_field in *. destruct (typeof a1); try discriminate.
    destruct (eval_lvalue ge e le m a1) as [[b0 p0]|] eqn:L; [|discriminate].
    rewrite (proj2 IH1 _ _ eq_refl). inversion H; subst. reflexivity.
  - rewrite ev_index in *. unfold lvalue_index, load_loc in *. destruct (typeof a1); try discriminate.
    destruct (eval_lvalue ge e le m a1) as [[b0 p0]|] eqn:L; [|discriminate].
    destruct (eval_expr ge e le m i) as [vi|] eqn:Ei; [|discriminate].
    rewrite (proj2 IH1 _ _ eq_refl), (proj1 IHi _ eq_refl).
    destruct vi; try discriminate; simpl;
      destruct ((0 <=? _)%Z && (_ <? _)%Z); try discriminate; apply (load_rel _ _ _ _ _ _ R H).
  - rewrite ev_lindex in *. unfold lvalue_index in *. destruct (typeof a1); try discriminate.
    destruct (eval_lvalue ge e le m a1) as [[b0 p0]|] eqn:L; [|discriminate].
    destruct (eval_expr ge e le m i) as [vi|] eqn:Ei; [|discriminate].
    rewrite (proj2 IH1 _ _ eq_refl), (proj1 IHi _ eq_refl).
    destruct vi; try discriminate; simpl;
      destruct ((0 <=? _)%Z && (_ <? _)%Z); try discriminate; inversion H; subst; reflexivity.
  - rewrite ev_cast in *. destruct (eval_expr ge e le m a1) as [v1|] eqn:E1; [|discriminate].
    rewrite (proj1 IH1 _ eq_refl), sem_cast_rv, H. reflexivity.
  - rewrite ev_unop in *. destruct (unop_type op (typeof a1)) as [ty'|] eqn:T; [|discriminate].
    destruct (eval_expr ge e le m a1) as [v1|] eqn:E1; [|discriminate].
    rewrite (proj1 IH1 _ eq_refl). destruct (type_eqb ty ty'); [|discriminate].
    apply (sem_unop_rv _ _ _ _ _ T H).
  - rewrite ev_binop in *. destruct (binop_type op (typeof a1)) as [ty'|] eqn:T; [|discriminate].
    destruct (eval_expr ge e le m a1) as [v1|] eqn:E1; [|discriminate].
    destruct (eval_expr ge e le m a2) as [v2|] eqn:E2; [|discriminate].
    rewrite (proj1 IH1 _ eq_refl), (proj1 IH2 _ eq_refl).
    destruct (type_eqb (typeof a1) (typeof a2) && type_eqb ty ty'); [|discriminate].
    apply (sem_binop_rv _ _ _ _ _ _ T H).
Qed.

Lemma eval_expr_rel:
  forall a v, eval_expr ge e le m a = Some v -> eval_expr geL (re e) (rle le) mL a = Some (rv v).
Proof. intros a; apply (proj1 (eval_rel a)). Qed.

Lemma eval_lvalue_rel:
  forall a b p, eval_lvalue ge e le m a = Some (b, p) -> eval_lvalue geL (re e) (rle le) mL a = Some (rb b, p).
Proof. intros a; apply (proj2 (eval_rel a)). Qed.

Lemma eval_exprlist_rel:
  forall al tl vl, eval_exprlist ge e le m al tl = Some vl ->
  eval_exprlist geL (re e) (rle le) mL al tl = Some (map rv vl).
Proof.
  induction al as [|a al IH]; intros [|t tl] vl H; simpl in *; try discriminate.
  - inversion H; auto.
  - destruct (eval_expr ge e le m a) as [v|] eqn:E; [|discriminate].
    rewrite (eval_expr_rel _ _ E), sem_cast_rv.
    destruct (sem_cast v t) as [v'|]; [|discriminate]. simpl.
    destruct (eval_exprlist ge e le m al tl) as [vl'|] eqn:E'; [|discriminate].
    rewrite (IH _ _ E'). inversion H; subst. reflexivity.
Qed.

Lemma eval_assign_rel:
  forall a1 a2 m', eval_assign ge e le m a1 a2 = Some m' ->
  exists mL', eval_assign geL (re e) (rle le) mL a1 a2 = Some mL' /\ mrel m' mL' /\ same_extra mL mL'.
Proof.
  intros a1 a2 m' H. unfold eval_assign in *.
  destruct (eval_lvalue ge e le m a1) as [[b p]|] eqn:L1; [|discriminate].
  rewrite (eval_lvalue_rel _ _ _ L1).
  destruct (typeof a1) eqn:T1;
    try (destruct (eval_expr ge e le m a2) as [v|] eqn:E2; [|discriminate];
         rewrite (eval_expr_rel _ _ E2); apply (store_rel _ _ _ _ _ _ _ R H)).
  destruct (typeof a2); try discriminate.
  destruct (eval_lvalue ge e le m a2) as [[b' p']|] eqn:L2; [|discriminate].
  rewrite (eval_lvalue_rel _ _ _ L2). destruct (ident_eq id id0); [|discriminate].
  destruct (load_path m b' p') as [mv|] eqn:LP; [|discriminate].
  rewrite (load_path_rel _ _ _ _ _ R LP). apply (store_path_rel _ _ _ _ _ _ R H).
Qed.

End EVAL.

(** *** Function entry and exit *)

Lemma alloc_vars_rel:
  forall ce ceL vars e m e' m1 mL,
  alloc_vars ce e m vars = (e', m1) -> mrel m mL ->
  (forall x ty, In (x, ty) vars -> undef_mval ceL ty = undef_mval ce ty) ->
  exists mL1, alloc_vars ceL (re e) mL vars = (re e', mL1) /\ mrel m1 mL1 /\ same_extra mL mL1.
Proof.
  induction vars as [|[x ty] vars IH]; intros e m e' m1 mL H R U; cbn [alloc_vars] in H |- *.
  - inversion H; subst. exists mL; split; auto. split; auto. apply same_extra_refl.
  - destruct (alloc m ty (undef_mval ce ty)) as [m2 b] eqn:A.
    destruct (alloc_rel _ _ _ _ _ _ R A) as (mL2 & A' & R2 & X2).
    rewrite rmv_undef in A'. rewrite (U x ty (or_introl eq_refl)). rewrite A'.
    rewrite set_assoc_re.
    destruct (IH _ _ _ _ _ H R2 (fun y t H' => U y t (or_intror H'))) as (mL1 & A1 & R1 & X1).
    exists mL1. split; auto. split; auto. eapply same_extra_trans; eauto.
Qed.

Lemma bind_params_rel:
  forall params vargs le le', bind_params params vargs le = Some le' ->
  bind_params params (map rv vargs) (rle le) = Some (rle le').
Proof.
  induction params as [|[x t] params IH]; intros [|v vargs] le le' H; simpl in *; try discriminate.
  - inversion H; auto.
  - rewrite set_assoc_rle. apply IH; auto.
Qed.

Lemma create_undef_temps_rle: forall temps, rle (create_undef_temps temps) = create_undef_temps temps.
Proof.
  intros temps. unfold create_undef_temps.
  assert (G: forall (l : list (ident * type)) le, rle le = le ->
             rle (fold_left (fun le (xt : ident * type) => set_assoc (fst xt) Vundef le) l le)
             = fold_left (fun le (xt : ident * type) => set_assoc (fst xt) Vundef le) l le).
  { induction l as [|xt l IH]; intros le E; simpl; auto. apply IH.
    change Vundef with (rv Vundef). rewrite <- set_assoc_rle, E. reflexivity. }
  apply G. reflexivity.
Qed.

Lemma free_vars_rel:
  forall e m mL, mrel m mL -> mrel (free_vars m e) (free_vars mL (re e)) /\ same_extra mL (free_vars mL (re e)).
Proof.
  induction e as [|[x [b t]] e IH]; intros m mL R; simpl.
  - split; auto. apply same_extra_refl.
  - destruct (free_rel _ _ b R) as [R1 X1]. destruct (IH _ _ R1) as [R2 X2].
    split; auto. eapply same_extra_trans; eauto.
Qed.

(** *** Traces and outcomes *)

Definition rev_ev (ev : event) : list event :=
  match ev with
  | Einit | Estep _ _ => []
  | Epublish tp mv => [Epublish tp (rmv mv)]
  | _ => [ev]
  end.

Definition rtrace (t : trace) : trace := flat_map rev_ev t.

Lemma rtrace_app: forall t1 t2, rtrace (t1 ++ t2) = rtrace t1 ++ rtrace t2.
Proof. intros; unfold rtrace; apply flat_map_app. Qed.

Definition rout (out : outcome) : outcome :=
  match out with
  | Out_return (Some v) => Out_return (Some (rv v))
  | o => o
  end.

Lemma rout_normal: forall out, rout out = Out_normal -> out = Out_normal.
Proof. intros [| |[v|]]; simpl; congruence. Qed.

Lemma rout_loop: forall out, rout (loop_outcome out) = loop_outcome (rout out).
Proof. intros [| |[v|]]; reflexivity. Qed.

Lemma outcome_result_rel:
  forall ty out v, outcome_result ty out = Some v -> outcome_result ty (rout out) = Some (rv v).
Proof.
  intros ty [| |[v'|]] v H; simpl in *; try (inversion H; subst; reflexivity); try discriminate.
  rewrite sem_cast_rv, H. reflexivity.
Qed.

Definition wr {CS CSL : Type} (w : world CS) : world CSL :=
  mkworld (w_subs w) (w_advertised w) (w_spins w) (w_ok w) None (w_time w).

Definition is_ctrl (ef : external_function) : bool :=
  match ef with
  | EF_controller_initialize _ _ | EF_controller_step _ _ => true
  | _ => false
  end.

(** ** The simulation *)

Section SIM.

Context {CS CSL : Type}.
Variables (ctx : ros_context CS) (ctxL : ros_context CSL) (ge geL : genv).
Hypothesis G : grel ge geL.
Hypothesis ARR : ctx_arrivals ctxL = ctx_arrivals ctx.
Hypothesis TIME : ctx_time ctxL = ctx_time ctx.
Hypothesis TGT : ctx_target ctxL = ctx_target ctx.

Local Notation ce := (ge_comp ge).
Local Notation ceL := (ge_comp geL).

Definition in_ge (fd : fundef) : Prop := exists x, find_funct ge x = Some fd.

(** A message struct that both programs convert alike. *)
Definition msg_ok (msgty : ident) : Prop :=
  forall mv, too_long ceL (Tstruct msgty) mv = too_long ce (Tstruct msgty) mv
          /\ clamp ceL (Tstruct msgty) mv = clamp ce (Tstruct msgty) mv.

(** A subscription whose messages both programs convert alike, and whose
    messages hold no pointer. *)
Definition sub_ok (s : subscription) : Prop :=
  msg_ok (sub_msgty s)
  /\ forall k a, In a (ctx_arrivals ctx k) -> ar_topic a = sub_topic s -> rmv (ar_msg a) = ar_msg a.

Hypothesis SUBS : forall topic msgty q targs tres,
  in_ge (External (EF_ros_subscribe topic msgty q) targs tres) -> forall cb, sub_ok (mksub topic msgty q cb).
Hypothesis PUBS : forall topic msgty targs tres,
  in_ge (External (EF_ros_publish topic msgty) targs tres) -> msg_ok msgty.
Hypothesis VARS : forall f, in_ge (Internal f) ->
  forall x ty, In (x, ty) (fn_vars f) -> undef_mval ceL ty = undef_mval ce ty.

Hypothesis LFD_int : forall f, lfd (Internal f) = Internal f.
Hypothesis LFD_ext : forall ef targs tres, is_ctrl ef = false -> lfd (External ef targs tres) = External ef targs tres.
Hypothesis LFD_type : forall fd, in_ge fd -> type_of_fundef (lfd fd) = type_of_fundef fd.

(** How the controller's state of the glue's environment is held in the
    linked program's memory. *)
Variable crel : option CS -> mem -> Prop.
Hypothesis CREL_extra : forall c mL mL', crel c mL -> same_extra mL mL' -> crel c mL'.
Hypothesis CTRL : forall ef targs tres vargs m w vres t m' w' mL,
  is_ctrl ef = true -> in_ge (External ef targs tres) ->
  external_call ctx ge ef vargs m w = Some (vres, t, m', w') ->
  mrel m mL -> crel (w_ctrl w) mL ->
  exists mL', eval_funcall ctxL geL mL (wr w) (lfd (External ef targs tres)) (map rv vargs) (rtrace t) mL' (wr w') (rv vres)
     /\ mrel m' mL' /\ crel (w_ctrl w') mL' /\ w_subs w' = w_subs w.

Definition subs_ok (w : world CS) : Prop := forall s, In s (w_subs w) -> sub_ok s.

Lemma external_rel:
  forall ef targs tres vargs m w vres t m' w' mL,
  is_ctrl ef = false -> in_ge (External ef targs tres) ->
  external_call ctx ge ef vargs m w = Some (vres, t, m', w') -> mrel m mL -> subs_ok w ->
  external_call ctxL geL ef (map rv vargs) mL (wr w) = Some (rv vres, rtrace t, mL, wr w')
  /\ mrel m' mL /\ w_ctrl w' = w_ctrl w /\ subs_ok w'.
Proof.
  intros ef targs tres vargs m w vres t m' w' mL NC IN H R S.
  destruct ef; try discriminate NC; simpl in H; destruct vargs as [|v1 [|v2 vargs]]; try discriminate;
    try (inversion H; subst; split; [reflexivity|split; [exact R|split; [reflexivity|exact S]]]);
    try (destruct v1; discriminate).
  - (* ros_ok *) simpl. destruct (w_ok w); inversion H; subst;
      (split; [reflexivity|split; [exact R|split; [reflexivity|exact S]]]).
  - (* subscribe *) destruct v1; try discriminate. inversion H; subst.
    split; [reflexivity|split; [exact R|split; [reflexivity|]]].
    intros s Hs. simpl in Hs. apply in_app_or in Hs as [Hs|[<-|[]]]; [apply S; auto|].
    simpl. eapply SUBS; eauto.
  - (* publish *) destruct v1 as [| | | | |b p|]; try discriminate. simpl.
    destruct (existsb (topic_eqb topic) (w_advertised w)); [|discriminate].
    destruct (load_path m b p) as [mv|] eqn:L; [|discriminate]. inversion H; subst.
    rewrite (load_path_rel _ _ _ _ _ R L). simpl.
    destruct (PUBS _ _ _ _ IN (rmv mv)) as [_ C]. rewrite C, clamp_rmv.
    split; [reflexivity|split; [exact R|split; [reflexivity|exact S]]].
Qed.

Lemma sim:
  (forall e le m w s t le' m' w' out, exec_stmt ctx ge e le m w s t le' m' w' out ->
     forall mL, mrel m mL -> crel (w_ctrl w) mL -> subs_ok w ->
     exists mL', exec_stmt ctxL geL (re e) (rle le) mL (wr w) s (rtrace t) (rle le') mL' (wr w') (rout out)
        /\ mrel m' mL' /\ crel (w_ctrl w') mL' /\ subs_ok w')
  /\ (forall m w fd vargs t m' w' v, eval_funcall ctx ge m w fd vargs t m' w' v ->
     in_ge fd -> forall mL, mrel m mL -> crel (w_ctrl w) mL -> subs_ok w ->
     exists mL', eval_funcall ctxL geL mL (wr w) (lfd fd) (map rv vargs) (rtrace t) mL' (wr w') (rv v)
        /\ mrel m' mL' /\ crel (w_ctrl w') mL' /\ subs_ok w')
  /\ (forall m w D t m' w', deliver ctx ge m w D t m' w' ->
     (forall s a, In (s, a) D -> msg_ok (sub_msgty s) /\ rmv (ar_msg a) = ar_msg a) ->
     forall mL, mrel m mL -> crel (w_ctrl w) mL -> subs_ok w ->
     exists mL', deliver ctxL geL mL (wr w) D (rtrace t) mL' (wr w')
        /\ mrel m' mL' /\ crel (w_ctrl w') mL' /\ subs_ok w').
Proof.
  apply exec_stmt_funcall_deliver_ind; intros.
  - (* skip *) exists mL; refine (conj _ (conj _ (conj _ _))); auto. constructor.
  - (* assign *) destruct (eval_assign_rel _ _ _ _ _ _ G H0 _ _ _ H) as (mL' & A & R' & X).
    exists mL'; refine (conj _ (conj _ (conj _ _))); eauto. constructor; auto.
  - (* set *) exists mL; refine (conj _ (conj _ (conj _ _))); auto. rewrite <- set_assoc_rle. constructor.
    apply (eval_expr_rel _ _ _ _ _ _ G H0 _ _ H).
  - (* call *)
    destruct (H5 (ex_intro _ fid H0) mL H6 H7 H8) as (mL' & C & R' & CR & S').
    exists mL'; refine (conj _ (conj _ (conj _ _))); auto.
    replace (rle (set_opttemp optid vres le)) with (set_opttemp optid (rv vres) (rle le))
      by (destruct optid; simpl; auto; apply set_assoc_rle).
    eapply exec_Scall with (fd := lfd fd) (vargs := map rv vargs).
    + apply (eval_expr_rel _ _ _ _ _ _ G H6 _ _ H).
    + apply (gr_funct _ _ G _ _ H0).
    + exact H1.
    + rewrite LFD_type; [exact H2 | exists fid; exact H0].
    + apply (eval_exprlist_rel _ _ _ _ _ _ G H6 _ _ _ H3).
    + exact C.
  - (* seq 1 *)
    destruct (H0 mL H3 H4 H5) as (mL1 & E1 & R1 & C1 & S1).
    destruct (H2 mL1 R1 C1 S1) as (mL2 & E2 & R2 & C2 & S2).
    exists mL2; refine (conj _ (conj _ (conj _ _))); auto. rewrite rtrace_app. eapply exec_Sseq_1; eauto.
  - (* seq 2 *)
    destruct (H0 mL H2 H3 H4) as (mL1 & E1 & R1 & C1 & S1).
    exists mL1; refine (conj _ (conj _ (conj _ _))); auto. eapply exec_Sseq_2; eauto.
    intros E; apply H1, rout_normal; auto.
  - (* if *)
    destruct (H2 mL H3 H4 H5) as (mL1 & E1 & R1 & C1 & S1).
    exists mL1; refine (conj _ (conj _ (conj _ _))); auto. eapply exec_Sifthenelse with (v := rv v) (b := b).
    + apply (eval_expr_rel _ _ _ _ _ _ G H3 _ _ H).
    + rewrite bool_val_rv; auto.
    + exact E1.
  - (* break *) exists mL; refine (conj _ (conj _ (conj _ _))); auto. constructor.
  - (* return none *) exists mL; refine (conj _ (conj _ (conj _ _))); auto. constructor.
  - (* return some *) exists mL; refine (conj _ (conj _ (conj _ _))); auto. constructor.
    apply (eval_expr_rel _ _ _ _ _ _ G H0 _ _ H).
  - (* loop *)
    destruct (H0 mL H3 H4 H5) as (mL1 & E1 & R1 & C1 & S1).
    destruct (H2 mL1 R1 C1 S1) as (mL2 & E2 & R2 & C2 & S2).
    exists mL2; refine (conj _ (conj _ (conj _ _))); auto. rewrite rtrace_app. eapply exec_Sloop_loop; eauto.
  - (* loop stop *)
    destruct (H0 mL H2 H3 H4) as (mL1 & E1 & R1 & C1 & S1).
    exists mL1; refine (conj _ (conj _ (conj _ _))); auto. rewrite rout_loop. eapply exec_Sloop_stop; eauto.
    intros E; apply H1, rout_normal; auto.
  - (* internal call *)
    unfold function_entry in H.
    destruct (alloc_vars (ge_comp ge) [] m (fn_vars f)) as [e0 m0] eqn:A.
    destruct (bind_params (fn_params f) vargs (create_undef_temps (fn_temps f))) as [le0|] eqn:B; [|discriminate].
    inversion H; subst e0 le0 m0. clear H.
    destruct (alloc_vars_rel _ _ _ _ _ _ _ mL A H4 (VARS f H3)) as (mL1 & A' & R1 & X1).
    assert (C1: crel (w_ctrl w) mL1) by eauto.
    destruct (H1 mL1 R1 C1 H6) as (mL2 & E2 & R2 & C2 & S2).
    destruct (free_vars_rel e _ _ R2) as [R3 X3].
    exists (free_vars mL2 (re e)). refine (conj _ (conj _ (conj _ _))); eauto.
    rewrite LFD_int. eapply eval_funcall_internal.
    + unfold function_entry. simpl in A'. rewrite A'.
      rewrite <- create_undef_temps_rle. rewrite (bind_params_rel _ _ _ _ B). reflexivity.
    + exact E2.
    + apply outcome_result_rel; auto.
  - (* external call *)
    destruct (is_ctrl ef) eqn:NC.
    + destruct (CTRL _ _ _ _ _ _ _ _ _ _ mL NC H0 H H1 H2) as (mL' & E & R' & C' & SW).
      exists mL'. refine (conj E (conj R' (conj C' _))). intros s0 Hs0. apply H3. rewrite <- SW. exact Hs0.
    + destruct (external_rel _ _ _ _ _ _ _ _ _ _ _ NC H0 H H1 H3) as (E & R' & C' & S').
      exists mL. rewrite LFD_ext by auto. refine (conj _ (conj _ (conj _ _))); auto.
      * apply eval_funcall_external. exact E.
      * rewrite C'; auto.
  - (* spinOnce *)
    assert (DA: forall s a, In (s, a) (spin_messages ctx w) -> msg_ok (sub_msgty s) /\ rmv (ar_msg a) = ar_msg a).
    { intros s a Hin.
      destruct (Loopfacts.In_spin_messages _ _ _ _ _ Hin) as (Hs & Ha & Ht).
      destruct (H4 s Hs) as [MO AP]. split; auto. eapply AP; eauto. }
    destruct (H0 DA mL H2 H3 H4) as (mL1 & D1 & R1 & C1 & S1).
    exists mL1. rewrite LFD_ext by reflexivity. refine (conj _ (conj _ (conj _ _))); auto.
    replace (wr (next_spin ctx w')) with (next_spin ctxL (wr (CSL:=CSL) w'))
      by (unfold next_spin, wr; simpl; rewrite TIME; reflexivity).
    simpl map. apply eval_funcall_spinOnce.
    replace (spin_messages ctxL (wr w)) with (spin_messages ctx w)
      by (unfold spin_messages, wr; simpl; rewrite ARR, TGT; reflexivity).
    exact D1.
  - (* deliver nil *) exists mL; refine (conj _ (conj _ (conj _ _))); auto. constructor.
  - (* deliver cons *)
    rename H into ACC, H0 into AL, H1 into FF, H2 into EV, H3 into IHE, H4 into DL, H5 into IHD, H6 into DA,
           H7 into R0, H8 into C0, H9 into S0.
    destruct (DA s a (or_introl eq_refl)) as [MO AP].
    destruct (alloc_rel _ _ _ _ _ _ R0 AL) as (mL1 & A1 & R1 & X1).
    assert (C1: crel (w_ctrl w) mL1) by eauto.
    destruct (IHE (ex_intro _ _ FF) mL1 R1 C1 S0) as (mL2 & E2 & R2 & C2 & S2).
    destruct (free_rel _ _ b R2) as [R3 X3].
    assert (C3: crel (w_ctrl w1) (free mL2 (rb b))) by eauto.
    destruct (IHD (fun s' a' H' => DA s' a' (or_intror H')) _ R3 C3 S2) as (mL4 & D4 & R4 & C4 & S4).
    exists mL4. refine (conj _ (conj _ (conj _ _))); auto. rewrite rtrace_app.
    eapply deliver_cons.
    + unfold accepted in *. destruct (MO (ar_msg a)) as [T _]. rewrite T. exact ACC.
    + unfold delivered in *. destruct (MO (ar_msg a)) as [_ Cl]. rewrite Cl.
      replace (clamp (ge_comp ge) (Tstruct (sub_msgty s)) (ar_msg a))
        with (rmv (clamp (ge_comp ge) (Tstruct (sub_msgty s)) (ar_msg a)))
        by (rewrite <- clamp_rmv, AP; reflexivity).
      exact A1.
    + apply (gr_funct _ _ G _ _ FF).
    + replace (set_time (wr w) (ar_time a)) with (wr (CSL:=CSL) (set_time w (ar_time a))) by reflexivity.
      exact E2.
    + exact D4.
  - (* deliver rejected *)
    destruct (H1 (fun s' a' H' => H2 s' a' (or_intror H')) mL H3 H4 H5) as (mL1 & D1 & R1 & C1 & S1).
    exists mL1. refine (conj _ (conj _ (conj _ _))); auto. apply deliver_rejected; auto.
    destruct (H2 s a (or_introl eq_refl)) as [MO _].
    unfold accepted in *. destruct (MO (ar_msg a)) as [T _]. rewrite T. exact H.
Qed.

End SIM.

End RENAME.

(** ** One more struct *)

(** Adding the controller's state struct after the glue's structs changes
    neither the values nor the conversions of the glue's types. *)

Section EXTEND.

Variables (ce : composite_env) (co : composite_definition).
Hypothesis WF : wf_composites ce.
Hypothesis FRESH : ~ In (co_name co) (composite_names ce).

Local Notation ceL := (ce ++ [co]).
Local Notation known := (composite_names ce).

Lemma find_composite_extend:
  forall id, In id known -> find_composite id ceL = find_composite id ce.
Proof.
  intros id H. unfold find_composite, composite_names in *. clear WF FRESH.
  induction ce as [|c l IH]; simpl in *; [contradiction|].
  destruct (string_dec (co_name c) id); auto. apply IH. destruct H; [contradiction|auto].
Qed.

Lemma struct_members_extend:
  forall id, In id known -> struct_members ceL id = struct_members ce id.
Proof. intros id H. unfold struct_members. rewrite find_composite_extend; auto. Qed.

Lemma members_complete:
  forall id ms f t, struct_members ce id = Some ms -> In (f, t) ms -> complete_type known t = true.
Proof. intros id ms f t SM I. apply (struct_members_complete ce id ms f t WF SM I). Qed.

Lemma default_mval_extend:
  forall dflt ty, complete_type known ty = true -> default_mval dflt ceL ty = default_mval dflt ce ty.
Proof.
  intros dflt ty C. unfold default_mval. rewrite rev_app_distr. simpl.
  apply (default_of_ext dflt _ _ known); auto.
  intros id I. simpl. destruct (ident_eq (co_name co) id); auto. subst. contradiction.
Qed.

Lemma clamp_extend:
  forall mv ty, complete_type known ty = true -> clamp ceL ty mv = clamp ce ty mv.
Proof.
  intros mv. induction mv as [v | fs IH | es IH] using mval_ind2; intros ty C.
  - reflexivity.
  - destruct ty; try reflexivity. simpl in C. apply in_ident_spec in C.
    rewrite !clamp_struct_eq. rewrite struct_members_extend by auto.
    destruct (struct_members ce id) as [ms|] eqn:SM; auto.
    assert (MC: forall f t, In (f, t) ms -> complete_type known t = true) by (intros; eapply members_complete; eauto).
    assert (F: clamp_fields ceL ms fs = clamp_fields ce ms fs).
    { clear SM. revert ms MC. induction IH as [|[g v] fs Hv IHfs IHrec]; intros ms MC; [destruct ms as [|[? ?] ?]; reflexivity|].
      destruct ms as [|[f t] ms]; [reflexivity|]. simpl in Hv |- *.
      rewrite (Hv t (MC f t (or_introl eq_refl))), IHrec; auto. intros; eapply MC; right; eauto. }
    rewrite F. destruct (bounded_name id); [|reflexivity].
    assert (S: clamp_seq ceL ms (clamp_fields ce ms fs) = clamp_seq ce ms (clamp_fields ce ms fs)).
    { unfold clamp_seq.
      destruct ms as [|[a1 t1] [|[a2 t2] [|[a3 t3] [|]]]]; auto.
      destruct t1 as [| [] [] | | | | | |]; auto; destruct t2 as [| [] [] | | | | | |]; auto.
      destruct t3 as [| | | | | t n | |]; auto.
      assert (Ct: complete_type known t = true).
      { assert (Ca := MC a3 (Tarray t n) ltac:(simpl; auto)). simpl in Ca. apply andb_true_iff in Ca; tauto. }
      unfold zero_mval. rewrite (default_mval_extend zero_val t Ct). reflexivity. }
    rewrite S. reflexivity.
  - destruct ty; simpl; auto. simpl in C. apply andb_true_iff in C as [_ C]. f_equal.
    apply map_ext_in. intros x I. rewrite Forall_forall in IH. apply IH; auto.
Qed.

Lemma too_long_extend:
  forall mv ty, complete_type known ty = true -> too_long ceL ty mv = too_long ce ty mv.
Proof.
  intros mv. induction mv as [v | fs IH | es IH] using mval_ind2; intros ty C.
  - reflexivity.
  - destruct ty; simpl; auto. simpl in C. apply in_ident_spec in C.
    rewrite struct_members_extend by auto.
    destruct (struct_members ce id) as [ms|] eqn:SM; auto.
    assert (MC: forall f t, In (f, t) ms -> complete_type known t = true) by (intros; eapply members_complete; eauto).
    f_equal. clear SM. revert ms MC. induction IH as [|[g v] fs Hv IHfs IHrec]; intros ms MC; [destruct ms as [|[? ?] ?]; reflexivity|].
    destruct ms as [|[f t] ms]; [reflexivity|]. simpl in Hv |- *.
    rewrite (Hv t (MC f t (or_introl eq_refl))), IHrec; auto. intros; eapply MC; right; eauto.
  - destruct ty; simpl; auto. simpl in C. apply andb_true_iff in C as [_ C].
    induction IH as [|x es Hx IHes IHrec]; simpl; auto. rewrite Hx, IHrec; auto.
Qed.

End EXTEND.

(** ** Allocating the globals of the linked program *)

Definition ldef (lfd : fundef -> fundef) (xd : ident * globdef) : ident * globdef :=
  match snd xd with
  | Gfun fd => (fst xd, Gfun (lfd fd))
  | Gvar _ => xd
  end.

Definition rvars (rb : block -> block) (vars : list (ident * (block * type))) : list (ident * (block * type)) :=
  map (fun xv => (fst xv, (rb (fst (snd xv)), snd (snd xv)))) vars.

Definition lfuns (lfd : fundef -> fundef) (funs : list (ident * fundef)) : list (ident * fundef) :=
  map (fun xf => (fst xf, lfd (snd xf))) funs.

Lemma alloc_globals_link:
  forall rb (RBinj : forall b1 b2, rb b1 = rb b2 -> b1 = b2) (RBsucc : forall b, rb (Pos.succ b) = Pos.succ (rb b))
         lfd X defs ge m geL mL ge' m',
  alloc_globals ge m defs = (ge', m') -> mrel rb m mL ->
  ge_vars geL = rvars rb (ge_vars ge) ++ X -> ge_funs geL = lfuns lfd (ge_funs ge) ->
  (forall x ty, In (x, Gvar ty) defs -> zero_mval (ge_comp geL) ty = zero_mval (ge_comp ge) ty) ->
  exists geL' mL', alloc_globals geL mL (map (ldef lfd) defs) = (geL', mL')
    /\ mrel rb m' mL' /\ same_extra rb mL mL' /\ ge_comp geL' = ge_comp geL
    /\ ge_vars geL' = rvars rb (ge_vars ge') ++ X /\ ge_funs geL' = lfuns lfd (ge_funs ge').
Proof.
  intros rb RBinj RBsucc lfd X. induction defs as [|[x [fd|ty]] defs IH]; intros ge m geL mL ge' m' A R V F Z;
    cbn [alloc_globals map ldef fst snd] in A |- *.
  - inversion A; subst. exists geL, mL.
    exact (conj eq_refl (conj R (conj (same_extra_refl _ _) (conj eq_refl (conj V F))))).
  - assert (F1: ge_funs (mkgenv (ge_comp geL) (ge_vars geL) ((x, lfd fd) :: ge_funs geL))
                = lfuns lfd (ge_funs (mkgenv (ge_comp ge) (ge_vars ge) ((x, fd) :: ge_funs ge))))
      by (simpl; rewrite F; reflexivity).
    destruct (IH _ _ (mkgenv (ge_comp geL) (ge_vars geL) ((x, lfd fd) :: ge_funs geL)) mL _ _ A R V F1)
      as (geL' & mL' & A' & R' & S' & C' & V' & F').
    { intros y t I. apply (Z y t). right. exact I. }
    exists geL', mL'. exact (conj A' (conj R' (conj S' (conj C' (conj V' F'))))).
  - destruct (alloc m ty (zero_mval (ge_comp ge) ty)) as [m1 b] eqn:AL.
    destruct (alloc_rel rb RBinj RBsucc _ _ _ _ _ _ R AL) as (mL1 & AL' & R1 & S1).
    rewrite rmv_zero in AL'. rewrite (Z x ty (or_introl eq_refl)), AL'.
    assert (V1: ge_vars (mkgenv (ge_comp geL) ((x, (rb b, ty)) :: ge_vars geL) (ge_funs geL))
                = rvars rb (ge_vars (mkgenv (ge_comp ge) ((x, (b, ty)) :: ge_vars ge) (ge_funs ge))) ++ X)
      by (simpl; rewrite V; reflexivity).
    destruct (IH _ _ (mkgenv (ge_comp geL) ((x, (rb b, ty)) :: ge_vars geL) (ge_funs geL)) mL1 _ _ A R1 V1 F)
      as (geL' & mL' & A' & R' & S' & C' & V' & F').
    { intros y t I. apply (Z y t). right. exact I. }
    exists geL', mL'. exact (conj A' (conj R' (conj (same_extra_trans _ _ _ _ S1 S') (conj C' (conj V' F'))))).
Qed.

Lemma find_assoc_rvars:
  forall rb x vars, find_assoc x (rvars rb vars) = option_map (fun bt => (rb (fst bt), snd bt)) (find_assoc x vars).
Proof. induction vars as [|[y [b t]] vars IH]; simpl; auto. destruct (string_dec x y); auto. Qed.

Lemma find_assoc_lfuns:
  forall lfd x funs, find_assoc x (lfuns lfd funs) = option_map lfd (find_assoc x funs).
Proof. induction funs as [|[y f] funs IH]; simpl; auto. destruct (string_dec x y); auto. Qed.

Lemma find_assoc_app_none:
  forall (A : Type) x (l1 l2 : list (ident * A)), find_assoc x l1 = None -> find_assoc x (l1 ++ l2) = find_assoc x l2.
Proof. induction l1 as [|[y a] l1 IH]; simpl; intros l2 H; auto. destruct (string_dec x y); [discriminate|auto]. Qed.

Lemma find_assoc_app_some:
  forall (A : Type) x (v : A) l1 l2, find_assoc x l1 = Some v -> find_assoc x (l1 ++ l2) = Some v.
Proof. induction l1 as [|[y a] l1 IH]; simpl; intros l2 H; [discriminate|]. destruct (string_dec x y); auto. Qed.
