(** * The generated controller computes the diagram's step *)

(** Main result, [step_correct]: for a well-formed diagram [d], in any
    global environment where the inputs, outputs and state globals are
    distinct blocks holding values of their struct types, calling
    [Controller_step] ([Diagramgen.step_function d]) terminates with no
    event, stores in the outputs global the outputs and in the state
    global the next state that [Diagram.dg_step] gives for the state and
    inputs it found there, and changes no other block; likewise
    [init_correct] for [Controller_initialize] and [Diagram.dg_init].

    The proof goes equation by equation: the temporaries hold the values
    of the signals computed so far ([temps_ok]), each equation's
    statement sets its signal's temporary to [eval_block]
    ([exec_eq_stmt]); then the outputs and the states are stored field
    by field. *)

From Coq Require Import String List ZArith Bool Lia.
From Flocq Require Import IEEE754.Binary.
From ROSGen Require Import Maps FloatOps Syntax Values Operators Memory Environment Semantics
                           NodeModel Diagram Diagramgen.
Import ListNotations.
Local Open Scope Z_scope.

(** ** Integers *)

Lemma pow2_pos: forall bits, 0 <= bits -> 0 < 2 ^ bits.
Proof. intros; apply Z.pow_pos_nonneg; lia. Qed.

Lemma wrap_signed_mod:
  forall bits n, 0 < bits -> wrap_signed bits (n mod 2 ^ bits) = wrap_signed bits n.
Proof.
  intros bits n Hb. unfold wrap_signed. rewrite Z.mod_mod by (apply Z.pow_nonzero; lia).
  reflexivity.
Qed.

Lemma wrap_unsigned_mod:
  forall bits n, 0 < bits -> wrap_unsigned bits (n mod 2 ^ bits) = wrap_unsigned bits n.
Proof.
  intros bits n Hb. unfold wrap_unsigned. apply Z.mod_mod. apply Z.pow_nonzero; lia.
Qed.

(** The arithmetic of [zop] commutes with reduction modulo [2^bits]. *)
Lemma zop_mod:
  forall op bits a b, op <> Adiv -> 0 < bits ->
  (zop op (a mod 2 ^ bits) (b mod 2 ^ bits)) mod 2 ^ bits = (zop op a b) mod 2 ^ bits.
Proof.
  intros op bits a b N Hb. assert (H := pow2_pos bits ltac:(lia)).
  destruct op; simpl; try congruence.
  - rewrite <- Z.add_mod by lia. reflexivity.
  - rewrite <- Zminus_mod. reflexivity.
  - rewrite <- Z.mul_mod by lia. reflexivity.
Qed.

Lemma in_range_wrap_unsigned:
  forall bits n, 0 < bits -> in_range bits Unsigned (wrap_unsigned bits n) = true.
Proof.
  intros bits n Hb. unfold in_range, int_min, int_max, wrap_unsigned.
  assert (H := Z.mod_pos_bound n (2 ^ bits) (pow2_pos bits ltac:(lia))).
  apply andb_true_iff; split; apply Z.leb_le; lia.
Qed.

Lemma in_range_of_norm:
  forall bits sg n, 0 < bits -> wrap bits sg n = n -> in_range bits sg n = true.
Proof.
  intros bits sg n Hb E. rewrite <- E. clear E.
  assert (Hh: 2 ^ bits = 2 * 2 ^ (bits - 1)).
  { replace bits with (Z.succ (bits - 1)) at 1 by lia. apply Z.pow_succ_r. lia. }
  assert (P := pow2_pos (bits - 1) ltac:(lia)).
  assert (Hm := Z.mod_pos_bound n (2 ^ bits) ltac:(lia)).
  unfold in_range, int_min, int_max; destruct sg; unfold wrap, wrap_signed, wrap_unsigned;
    apply andb_true_iff; split; apply Z.leb_le.
  - destruct (n mod 2 ^ bits <? 2 ^ (bits - 1)) eqn:L;
      [apply Z.ltb_lt in L | apply Z.ltb_ge in L]; lia.
  - destruct (n mod 2 ^ bits <? 2 ^ (bits - 1)) eqn:L;
      [apply Z.ltb_lt in L | apply Z.ltb_ge in L]; lia.
  - lia.
  - lia.
Qed.

(** ** Values of a type *)

Definition typed (v : val) (q : prim) : Prop := val_has_type v (ct q).

Lemma val_of_prim_typed: forall v q, val_of_prim v q = true -> typed v q.
Proof. intros v q H. apply val_has_typeb_correct. exact H. Qed.

(** The shape of a value of each signal type. *)
Lemma typed_int32: forall v, typed v Pint32 -> exists n, v = Vint n /\ wrap_signed 32 n = n.
Proof. intros [] H; simpl in H; try contradiction; eauto. Qed.
Lemma typed_uint32: forall v, typed v Puint32 -> exists n, v = Vint n /\ wrap_unsigned 32 n = n.
Proof. intros [] H; simpl in H; try contradiction; eauto. Qed.
Lemma typed_int64: forall v, typed v Pint64 -> exists n, v = Vlong n /\ wrap_signed 64 n = n.
Proof. intros [] H; simpl in H; try contradiction; eauto. Qed.
Lemma typed_uint64: forall v, typed v Puint64 -> exists n, v = Vlong n /\ wrap_unsigned 64 n = n.
Proof. intros [] H; simpl in H; try contradiction; eauto. Qed.
Lemma typed_float64: forall v, typed v Pfloat64 -> exists x, v = Vfloat x.
Proof. intros [] H; simpl in H; try contradiction; eauto. Qed.
Lemma typed_float32: forall v, typed v Pfloat32 -> exists x, v = Vsingle x.
Proof. intros [] H; simpl in H; try contradiction; eauto. Qed.
Lemma typed_bool: forall v, typed v Pbool -> exists n, v = Vint n /\ wrap_unsigned 8 n = n.
Proof. intros [] H; simpl in H; try contradiction; eauto. Qed.

Ltac typed_inv :=
  repeat match goal with
  | H : typed ?v Pint32 |- _ => destruct (typed_int32 v H) as [? [? ?]]; clear H; subst v
  | H : typed ?v Puint32 |- _ => destruct (typed_uint32 v H) as [? [? ?]]; clear H; subst v
  | H : typed ?v Pint64 |- _ => destruct (typed_int64 v H) as [? [? ?]]; clear H; subst v
  | H : typed ?v Puint64 |- _ => destruct (typed_uint64 v H) as [? [? ?]]; clear H; subst v
  | H : typed ?v Pfloat64 |- _ => destruct (typed_float64 v H) as [? ?]; clear H; subst v
  | H : typed ?v Pfloat32 |- _ => destruct (typed_float32 v H) as [? ?]; clear H; subst v
  | H : typed ?v Pbool |- _ => destruct (typed_bool v H) as [? [? ?]]; clear H; subst v
  end.

(** ** Expressions *)

Section EXPR.

Variable ge : genv.
Variable le : temp_env.
Variable m : mem.

Definition ev (a : expr) : option val := eval_expr ge [] le m a.

Lemma ev_const: forall v q, sig_prim q = true -> typed v q -> ev (const_expr v q) = Some v.
Proof.
  intros v q S T. destruct q; simpl in S; try discriminate; typed_inv; unfold ev; cbn;
    try reflexivity; try congruence.
  (* bool: (unsigned char)n with 0 <= n < 256 *)
  assert (B := Z.mod_pos_bound x (2 ^ 8) ltac:(lia)). unfold wrap_unsigned in H0.
  rewrite H0 in B. change (2 ^ 8) with 256 in B.
  assert (E: wrap_signed 32 x = x).
  { unfold wrap_signed. rewrite Z.mod_small by (simpl; lia).
    destruct (x <? 2 ^ (32 - 1)) eqn:L; [reflexivity|]. apply Z.ltb_ge in L. simpl in L. lia. }
  unfold norm_int; simpl. rewrite E. unfold wrap_unsigned. rewrite H0. reflexivity.
Qed.

Lemma arith_typed:
  forall op q a b, num_prim q = true ->
  typed a q -> typed b q -> (op <> Adiv \/ float_prim q = true) -> typed (arith op q a b) q.
Proof.
  intros op q a b N Ta Tb D.
  destruct q; simpl in N; try discriminate; typed_inv; simpl; try exact I;
    (destruct op; [| | |destruct D as [D|D]; [congruence|discriminate]]);
    unfold typed, ct; simpl; unfold norm_int, norm_long; simpl;
    first [ exact (wrap_idem 32 Signed _ ltac:(lia)) | exact (wrap_idem 32 Unsigned _ ltac:(lia))
          | exact (wrap_idem 64 Signed _ ltac:(lia)) | exact (wrap_idem 64 Unsigned _ ltac:(lia)) ].
Qed.

Lemma ev_tmp: forall x q v, find_assoc (temp_of x) le = Some v -> ev (tmp x q) = Some v.
Proof. intros; unfold ev, tmp; simpl; auto. Qed.

Lemma type_eqb_refl: forall t, type_eqb t t = true.
Proof. intros; apply type_eqb_true; reflexivity. Qed.

(** A wrapped unsigned computation, converted to the signed type. *)
Lemma wrap_signed_via_unsigned:
  forall bits op a b, 0 < bits -> op <> Adiv ->
  wrap_signed bits (wrap_unsigned bits (zop op (wrap_unsigned bits a) (wrap_unsigned bits b)))
  = wrap_signed bits (zop op a b).
Proof.
  intros bits op a b Hb N. unfold wrap_unsigned.
  rewrite wrap_signed_mod by lia. rewrite <- (wrap_signed_mod bits (zop op a b)) by lia.
  rewrite <- zop_mod by auto. rewrite wrap_signed_mod by lia. reflexivity.
Qed.

Lemma in_range_norm_int: forall sg n, in_range 32 sg (norm_int I32 sg n) = true.
Proof. intros; apply in_range_of_norm; [lia|]. apply (wrap_idem 32 sg); lia. Qed.
Lemma in_range_norm_long: forall sg n, in_range 64 sg (norm_long sg n) = true.
Proof. intros; apply in_range_of_norm; [lia|]. apply (wrap_idem 64 sg); lia. Qed.

Ltac signed_case bits :=
  match goal with D : ?op <> Adiv \/ _ |- _ =>
    destruct op; [| | |destruct D as [D|D]; [congruence|discriminate]];
    simpl; unfold int_binop; rewrite !in_range_wrap_unsigned by lia; simpl;
    do 2 f_equal;
    match goal with
    | |- wrap_signed _ (wrap_unsigned _ (wrap_unsigned _ ?a + wrap_unsigned _ ?b)) = _ =>
        exact (wrap_signed_via_unsigned bits Aadd a b ltac:(lia) ltac:(discriminate))
    | |- wrap_signed _ (wrap_unsigned _ (wrap_unsigned _ ?a - wrap_unsigned _ ?b)) = _ =>
        exact (wrap_signed_via_unsigned bits Asub a b ltac:(lia) ltac:(discriminate))
    | |- wrap_signed _ (wrap_unsigned _ (wrap_unsigned _ ?a * wrap_unsigned _ ?b)) = _ =>
        exact (wrap_signed_via_unsigned bits Amul a b ltac:(lia) ltac:(discriminate))
    end
  end.

Lemma ev_arith:
  forall op q a b va vb, num_prim q = true -> (op <> Adiv \/ float_prim q = true) ->
  ev a = Some va -> ev b = Some vb -> typed va q -> typed vb q ->
  typeof a = ct q -> typeof b = ct q ->
  ev (arith_expr op q a b) = Some (arith op q va vb).
Proof.
  intros op q a b va vb N D Ha Hb Ta Tb TA TB. unfold ev in *.
  destruct q; simpl in N; try discriminate; typed_inv; unfold arith_expr; simpl unsigned_of;
    cbn - [int_binop]; rewrite Ha, Hb; cbn - [int_binop].
  - signed_case 32.
  - rewrite TA, TB.
    assert (R0: in_range 32 Unsigned x0 = true) by (apply in_range_of_norm; [lia | exact H1]).
    assert (R1: in_range 32 Unsigned x = true) by (apply in_range_of_norm; [lia | exact H0]).
    destruct op; [| | |destruct D as [D|D]; [congruence|discriminate]];
    simpl; unfold int_binop; rewrite R0, R1; reflexivity.
  - signed_case 64.
  - rewrite TA, TB.
    assert (R0: in_range 64 Unsigned x0 = true) by (apply in_range_of_norm; [lia | exact H1]).
    assert (R1: in_range 64 Unsigned x = true) by (apply in_range_of_norm; [lia | exact H0]).
    destruct op; [| | |destruct D as [D|D]; [congruence|discriminate]];
    simpl; unfold int_binop; rewrite R0, R1; reflexivity.
  - rewrite TA, TB. destruct op; reflexivity.
  - rewrite TA, TB. destruct op; reflexivity.
Qed.

Lemma wrap_signed_neg_via_unsigned:
  forall bits x, 0 < bits ->
  wrap_signed bits (wrap_unsigned bits (- wrap_unsigned bits x)) = wrap_signed bits (- x).
Proof.
  intros bits x Hb.
  assert (Z0: wrap_unsigned bits 0 = 0) by (unfold wrap_unsigned; apply Z.mod_0_l; apply Z.pow_nonzero; lia).
  replace (- wrap_unsigned bits x) with (wrap_unsigned bits 0 - wrap_unsigned bits x) by lia.
  replace (- x) with (0 - x) by lia.
  exact (wrap_signed_via_unsigned bits Asub 0 x Hb ltac:(discriminate)).
Qed.

Lemma ev_neg:
  forall q a va, num_prim q = true -> ev a = Some va -> typed va q -> typeof a = ct q ->
  ev (neg_expr q a) = Some (negate q va).
Proof.
  intros q a va N Ha Ta TA. unfold ev in *.
  destruct q; simpl in N; try discriminate; typed_inv; unfold neg_expr; simpl unsigned_of;
    cbn - [sem_unop]; rewrite ?Ha; cbn - [sem_unop]; rewrite ?TA; simpl.
  - rewrite in_range_wrap_unsigned by lia. simpl. do 2 f_equal.
    apply wrap_signed_neg_via_unsigned; lia.
  - rewrite (in_range_of_norm 32 Unsigned x) by (auto; lia). reflexivity.
  - rewrite in_range_wrap_unsigned by lia. simpl. do 2 f_equal.
    apply wrap_signed_neg_via_unsigned; lia.
  - rewrite (in_range_of_norm 64 Unsigned x) by (auto; lia). reflexivity.
  - reflexivity.
  - reflexivity.
Qed.

(** Comparisons are defined on values of their type. *)
Lemma sem_cmp:
  forall op q va vb, num_prim q = true -> typed va q -> typed vb q ->
  sem_binop (cmp_op op) (ct q) va vb = Some (int_of_bool (compare op q va vb)).
Proof.
  intros op q va vb N Ta Tb. unfold compare.
  assert (E: exists b, sem_binop (cmp_op op) (ct q) va vb = Some (int_of_bool b)).
  { destruct q; simpl in N; try discriminate; typed_inv; simpl; unfold int_binop;
      repeat match goal with
      | H : wrap_signed ?bits ?n = ?n |- context [in_range ?bits Signed ?n] =>
          rewrite (in_range_of_norm bits Signed n) by (auto; lia)
      | H : wrap_unsigned ?bits ?n = ?n |- context [in_range ?bits Unsigned ?n] =>
          rewrite (in_range_of_norm bits Unsigned n) by (auto; lia)
      end;
      destruct op; simpl; eauto. }
  destruct E as [b E]. unfold ct in *. rewrite E. destruct b; reflexivity.
Qed.

Lemma ev_cmp:
  forall op q a b va vb, num_prim q = true -> ev a = Some va -> ev b = Some vb ->
  typed va q -> typed vb q -> typeof a = ct q -> typeof b = ct q ->
  ev (cmp_expr op q a b) = Some (int_of_bool (compare op q va vb)).
Proof.
  intros op q a b va vb N Ha Hb Ta Tb TA TB. unfold ev, cmp_expr in *. cbn - [sem_binop binop_type].
  rewrite TA, TB, Ha, Hb.
  assert (BT: binop_type (cmp_op op) (ct q) = Some tint).
  { unfold binop_type. destruct q; simpl in N; try discriminate; destruct op; reflexivity. }
  rewrite BT, !type_eqb_refl. simpl. apply sem_cmp; auto.
Qed.

Lemma bool_val_int_of_bool: forall b, bool_val (int_of_bool b) = Some b.
Proof. destruct b; reflexivity. Qed.

Lemma uchar_int: forall n, wrap_unsigned 8 n = n -> wrap_signed 32 n = n /\ 0 <= n < 256.
Proof.
  intros n H. assert (B := Z.mod_pos_bound n (2 ^ 8) ltac:(lia)).
  unfold wrap_unsigned in H. rewrite H in B. change (2 ^ 8) with 256 in B.
  split; [|lia]. unfold wrap_signed. rewrite Z.mod_small by (simpl; lia).
  destruct (n <? 2 ^ (32 - 1)) eqn:L; [reflexivity|]. apply Z.ltb_ge in L. simpl in L. lia.
Qed.

Lemma ev_truth:
  forall a v, ev a = Some v -> typed v Pbool ->
  ev (truth_expr a) = Some (int_of_bool (truth v)).
Proof.
  intros a v Ha T. typed_inv. unfold ev, truth_expr in *. cbn - [sem_binop].
  rewrite Ha. cbn - [sem_binop].
  destruct (uchar_int _ H0) as [E _]. unfold norm_int. simpl. rewrite E.
  simpl. unfold int_binop.
  rewrite (in_range_of_norm 32 Signed x) by (auto; lia). simpl.
  unfold truth. simpl. destruct (x =? 0); reflexivity.
Qed.

(** A left fold of [& | ^] over truth values. *)
Lemma ev_fold_bool:
  forall bop f, (forall b1 b2, sem_binop bop tint (int_of_bool b1) (int_of_bool b2) = Some (int_of_bool (f b1 b2))) ->
  binop_type bop tint = Some tint ->
  forall ts bs acc b0,
  Forall2 (fun t b => ev t = Some (int_of_bool b) /\ typeof t = tint) ts bs ->
  ev acc = Some (int_of_bool b0) -> typeof acc = tint ->
  ev (fold_left (fun (acc : expr) (t' : expr) => Ebinop bop acc t' tint) ts acc)
  = Some (int_of_bool (fold_left f bs b0)).
Proof.
  intros bop f F BT ts bs acc b0 A; revert acc b0. induction A as [|t b ts bs [Et Tt] A IH];
    intros acc b0 Ha Ta; simpl; auto.
  apply IH; [|reflexivity]. unfold ev in *. cbn - [sem_binop binop_type].
  rewrite Ta, Tt, Ha, Et, BT, !type_eqb_refl. simpl. apply F.
Qed.

Lemma fold_andb: forall l b, fold_left andb l b = b && forallb id l.
Proof. induction l as [|x l IH]; intros b; simpl; [destruct b; reflexivity|]. rewrite IH. destruct b, x; reflexivity. Qed.
Lemma fold_orb: forall l b, fold_left orb l b = b || existsb id l.
Proof. induction l as [|x l IH]; intros b; simpl; [destruct b; reflexivity|]. rewrite IH. destruct b, x; reflexivity. Qed.

Lemma F_and: forall b1 b2, sem_binop Oand tint (int_of_bool b1) (int_of_bool b2) = Some (int_of_bool (andb b1 b2)).
Proof. intros [] []; reflexivity. Qed.
Lemma F_or: forall b1 b2, sem_binop Oor tint (int_of_bool b1) (int_of_bool b2) = Some (int_of_bool (orb b1 b2)).
Proof. intros [] []; reflexivity. Qed.
Lemma F_xor: forall b1 b2, sem_binop Oxor tint (int_of_bool b1) (int_of_bool b2) = Some (int_of_bool (xorb b1 b2)).
Proof. intros [] []; reflexivity. Qed.

Lemma ev_logic:
  forall op ts bs, Forall2 (fun t b => ev t = Some (int_of_bool b) /\ typeof t = tint) ts bs ->
  (match op, bs with Lnot, [_] => True | Lnot, _ => False | _, _ :: _ :: _ => True | _, _ => False end) ->
  ev (logic_expr op ts) = Some (int_of_bool (logic op bs)).
Proof.
  intros op ts bs A Sh.
  destruct A as [|t b ts bs [Et Tt] A]; [destruct op; contradiction|].
  assert (AND: ev (fold_left (fun (acc : expr) (t' : expr) => Ebinop Oand acc t' tint) ts t)
               = Some (int_of_bool (forallb id (b :: bs)))).
  { rewrite (ev_fold_bool Oand andb F_and eq_refl ts bs t b A Et Tt).
    simpl. rewrite fold_andb. reflexivity. }
  assert (OR: ev (fold_left (fun (acc : expr) (t' : expr) => Ebinop Oor acc t' tint) ts t)
               = Some (int_of_bool (existsb id (b :: bs)))).
  { rewrite (ev_fold_bool Oor orb F_or eq_refl ts bs t b A Et Tt).
    simpl. rewrite fold_orb. reflexivity. }
  assert (NOT: forall e c, ev e = Some (int_of_bool c) -> typeof e = tint ->
                 ev (Eunop Onotbool e tint) = Some (int_of_bool (negb c))).
  { intros e c Ee Te. unfold ev in *. cbn - [sem_unop]. rewrite Te, Ee. simpl.
    destruct c; reflexivity. }
  assert (TF: forall (bop : binary_operation) (l : list expr) (a : expr), typeof a = tint ->
            typeof (fold_left (fun (acc : expr) (t' : expr) => Ebinop bop acc t' tint) l a) = tint).
  { intros bop l; induction l; simpl; auto. }
  destruct op; simpl.
  - exact AND.
  - exact OR.
  - apply NOT; [exact AND | apply TF; auto].
  - apply NOT; [exact OR | apply TF; auto].
  - rewrite (ev_fold_bool Oxor xorb F_xor eq_refl ts bs t b A Et Tt). destruct b; reflexivity.
  - apply NOT; [exact AND | apply TF; auto].
Qed.

End EXPR.

(** ** Statements *)

Lemma set_assoc_twice:
  forall A x (v v' : A) l, set_assoc x v (set_assoc x v' l) = set_assoc x v l.
Proof.
  induction l as [|[y z] l IH]; simpl.
  - destruct (ident_eq x x); congruence.
  - destruct (ident_eq x y) as [E|N]; simpl.
    + destruct (ident_eq x y); congruence.
    + destruct (ident_eq x y); [congruence|]. rewrite IH. reflexivity.
Qed.

Lemma append_inj: forall p a b, (p ++ a)%string = (p ++ b)%string -> a = b.
Proof. induction p as [|c p IH]; simpl; intros a b H; [auto|]. inversion H; auto. Qed.

Lemma temp_of_inj: forall a b, temp_of a = temp_of b -> a = b.
Proof. intros a b H. exact (append_inj _ _ _ H). Qed.

Section STMT.

Context {CS : Type}.
Variable ctx : ros_context CS.
Variable ge : genv.

Lemma exec_seq:
  forall e le m w s1 s2 le1 m1 le2 m2,
  exec_stmt ctx ge e le m w s1 [] le1 m1 w Out_normal ->
  exec_stmt ctx ge e le1 m1 w s2 [] le2 m2 w Out_normal ->
  exec_stmt ctx ge e le m w (Ssequence s1 s2) [] le2 m2 w Out_normal.
Proof. intros. change (@nil event) with (@nil event ++ []). econstructor; eauto. Qed.

Lemma exec_set:
  forall le m w x a v, eval_expr ge [] le m a = Some v ->
  exec_stmt ctx ge [] le m w (Sset x a) [] (set_assoc x v le) m w Out_normal.
Proof. intros; constructor; auto. Qed.

Lemma exec_if:
  forall le m w c v b s1 s2 le' m',
  eval_expr ge [] le m c = Some v -> bool_val v = Some b ->
  exec_stmt ctx ge [] le m w (if b then s1 else s2) [] le' m' w Out_normal ->
  exec_stmt ctx ge [] le m w (Sifthenelse c s1 s2) [] le' m' w Out_normal.
Proof. intros; econstructor; eauto. Qed.

Variable d : diagram.
Variables (m : mem) (w : world CS) (s u : mval) (bu bs : block).
Hypothesis HU : find_var ge (dg_in_var d) = Some (bu, Tstruct (dg_in_struct d)).
Hypothesis HUm : exists ty, get_block m bu = Some (ty, u).
Hypothesis Uty : forall f q, find_assoc f (dg_inputs d) = Some q ->
  exists v, mval_get u [Sfield f] = Some (MVscalar v) /\ typed v q.
Hypothesis HS : has_states d = true ->
  find_var ge (dg_state_var d) = Some (bs, Tstruct (dg_state_struct d))
  /\ exists ty, get_block m bs = Some (ty, s).
Hypothesis Sty : forall st, In st (dg_states d) ->
  exists v, mval_get s [Sfield (st_name st)] = Some (MVscalar v) /\ typed v (st_type st).

(** The temporaries hold the signals of [tctx]. *)
Definition temps_ok (tctx : list (ident * prim)) (env : senv) (le : temp_env) : Prop :=
  forall x q, find_assoc x tctx = Some q ->
  find_assoc (temp_of x) le = Some (sig env x) /\ typed (sig env x) q.

Lemma ev_field_mem:
  forall mm le b x sid mv f q v,
  find_var ge x = Some (b, Tstruct sid) -> (exists t, get_block mm b = Some (t, mv)) ->
  mval_get mv [Sfield f] = Some (MVscalar v) -> sig_prim q = true ->
  eval_expr ge [] le mm (Efield (Evar x (Tstruct sid)) f (ct q)) = Some v.
Proof.
  intros mm le b x sid mv f q v F [t G] M S. cbn.
  rewrite F. unfold load_loc, load.
  assert (SC: is_scalar_type (ct q) = true) by (destruct q; reflexivity).
  rewrite SC. unfold load_path. rewrite G. simpl in M |- *. rewrite M. reflexivity.
Qed.

Lemma ev_field:
  forall le b x sid mv f q v,
  find_var ge x = Some (b, Tstruct sid) -> (exists t, get_block m b = Some (t, mv)) ->
  mval_get mv [Sfield f] = Some (MVscalar v) -> sig_prim q = true ->
  eval_expr ge [] le m (Efield (Evar x (Tstruct sid)) f (ct q)) = Some v.
Proof. intros; eapply ev_field_mem; eauto. Qed.

Lemma tmp_any_mem: forall le mm mm' x q, eval_expr ge [] le mm (tmp x q) = eval_expr ge [] le mm' (tmp x q).
Proof. reflexivity. Qed.

Lemma typeof_tmp: forall x q, typeof (tmp x q) = ct q.
Proof. reflexivity. Qed.
Lemma typeof_const: forall v q, typeof (const_expr v q) = ct q.
Proof. intros [] q; try destruct q; reflexivity. Qed.
Lemma typeof_arith: forall op q a b, typeof (arith_expr op q a b) = ct q.
Proof. intros op q a b; unfold arith_expr; destruct (unsigned_of q); reflexivity. Qed.
Lemma typeof_neg: forall q a, typeof (neg_expr q a) = ct q.
Proof. intros q a; unfold neg_expr; destruct (unsigned_of q); reflexivity. Qed.

Lemma has_type_spec:
  forall tctx x q, has_type tctx x q = true -> find_assoc x tctx = Some q.
Proof.
  unfold has_type, has_type_l, sig_type. intros tctx x q H.
  destruct (find_assoc x tctx) as [q'|]; [|discriminate].
  apply prim_eqb_true in H. subst; reflexivity.
Qed.

Section BLOCK.

Variables (tctx : list (ident * prim)) (env : senv) (le : temp_env).
Hypothesis TOK : temps_ok tctx env le.

Lemma tmp_ok: forall x q, has_type tctx x q = true ->
  eval_expr ge [] le m (tmp x q) = Some (sig env x) /\ typed (sig env x) q.
Proof.
  intros x q H. apply has_type_spec in H. destruct (TOK x q H) as [A B].
  split; auto.
Qed.

Lemma num_sig: forall q, num_prim q = true -> sig_prim q = true.
Proof. intros q H. unfold num_prim in H. apply andb_true_iff in H. tauto. Qed.

Lemma negate_typed: forall q a, num_prim q = true -> typed a q -> typed (negate q a) q.
Proof.
  intros q a N T. destruct q; simpl in N; try discriminate; typed_inv; simpl; try exact I;
    unfold typed, ct; simpl; unfold norm_int, norm_long; simpl;
    first [ exact (wrap_idem 32 Signed _ ltac:(lia)) | exact (wrap_idem 32 Unsigned _ ltac:(lia))
          | exact (wrap_idem 64 Signed _ ltac:(lia)) | exact (wrap_idem 64 Unsigned _ ltac:(lia)) ].
Qed.

Lemma of_bool_typed: forall b, typed (of_bool b) Pbool.
Proof. destruct b; reflexivity. Qed.

Lemma of_bool_int: forall b, of_bool b = int_of_bool b.
Proof. reflexivity. Qed.

(** [Sum]: the fold of the terms. *)
Lemma ev_sum:
  forall q terms acc accv, num_prim q = true ->
  forallb (fun t => has_type tctx (snd t) q) terms = true ->
  eval_expr ge [] le m acc = Some accv -> typed accv q -> typeof acc = ct q ->
  let r := fold_left (fun (a : val) (t : bool * ident) =>
                        arith (if fst t then Aadd else Asub) q a (sig env (snd t))) terms accv in
  eval_expr ge [] le m
    (fold_left (fun (a : expr) (t : bool * ident) => arith_expr (if fst t then Aadd else Asub) q a (tmp (snd t) q))
               terms acc) = Some r /\ typed r q.
Proof.
  intros q terms; induction terms as [|[p y] terms IH]; intros acc accv N F Ea Ta TA; simpl; auto.
  simpl in F. apply andb_true_iff in F as [Fy F].
  destruct (tmp_ok y q Fy) as [Ey Ty].
  assert (D: (if p then Aadd else Asub) <> Adiv) by (destruct p; discriminate).
  apply IH; auto.
  - apply ev_arith; auto.
  - apply arith_typed; auto.
  - apply typeof_arith.
Qed.

Lemma state_type_In:
  forall x q, state_type d x = Some q ->
  exists st, In st (dg_states d) /\ st_name st = x /\ st_type st = q.
Proof.
  unfold state_type. intros x q H.
  destruct (find (fun st => String.eqb (st_name st) x) (dg_states d)) as [st|] eqn:F; [|discriminate].
  simpl in H. inversion H; subst. apply find_some in F as [I E].
  apply String.eqb_eq in E. eauto.
Qed.

Lemma has_states_In: forall st, In st (dg_states d) -> has_states d = true.
Proof. intros st I. unfold has_states. destruct (dg_states d); [contradiction | reflexivity]. Qed.

(** [x := a; if (b < x) x = b; ...] computes the MinMax fold. *)
Lemma exec_minmax:
  forall (x : ident) (q : prim) (ismax : bool) (args : list ident) (xv : val),
  num_prim q = true -> forallb (fun a => has_type tctx a q) args = true ->
  find_assoc x tctx = None -> typed xv q ->
  exec_stmt ctx ge [] (set_assoc (temp_of x) xv le) m w
    (fold_right (fun (b : ident) (k : statement) => Ssequence
       (Sifthenelse (cmp_expr (if ismax then Rgt else Rlt) q (tmp b q) (Etempvar (temp_of x) (ct q)))
                    (Sset (temp_of x) (tmp b q)) Sskip) k) Sskip args)
    [] (set_assoc (temp_of x)
          (fold_left (fun (v : val) (b : ident) =>
                        if compare (if ismax then Rgt else Rlt) q (sig env b) v then sig env b else v)
                     args xv) le) m w Out_normal
  /\ typed (fold_left (fun (v : val) (b : ident) =>
                        if compare (if ismax then Rgt else Rlt) q (sig env b) v then sig env b else v)
                     args xv) q.
Proof.
  intros x q ismax args; induction args as [|b args IH]; intros xv N F X T; simpl.
  - split; auto. constructor.
  - simpl in F. apply andb_true_iff in F as [Fb F].
    destruct (tmp_ok b q Fb) as [Eb Tb].
    assert (NE: temp_of b <> temp_of x).
    { intros E. apply temp_of_inj in E. subst b. apply has_type_spec in Fb. congruence. }
    assert (Eb': eval_expr ge [] (set_assoc (temp_of x) xv le) m (tmp b q) = Some (sig env b)).
    { unfold tmp in *. cbn in Eb |- *. rewrite find_assoc_set_other by auto. exact Eb. }
    assert (Ex: eval_expr ge [] (set_assoc (temp_of x) xv le) m (Etempvar (temp_of x) (ct q)) = Some xv).
    { cbn. apply find_assoc_set_same. }
    assert (Ec := ev_cmp ge (set_assoc (temp_of x) xv le) m (if ismax then Rgt else Rlt) q
                    (tmp b q) (Etempvar (temp_of x) (ct q)) (sig env b) xv N Eb' Ex Tb T
                    eq_refl eq_refl).
    destruct (compare (if ismax then Rgt else Rlt) q (sig env b) xv) eqn:C.
    + destruct (IH (sig env b) N F X Tb) as [IHe IHt].
      split; [|exact IHt].
      eapply exec_seq; [|exact IHe].
      eapply exec_if; [exact Ec | apply bool_val_int_of_bool |]. simpl.
      rewrite <- (set_assoc_twice _ (temp_of x) (sig env b) xv le).
      apply exec_set; exact Eb'.
    + destruct (IH xv N F X T) as [IHe IHt].
      split; [|exact IHt].
      eapply exec_seq; [|exact IHe].
      eapply exec_if; [exact Ec | apply bool_val_int_of_bool |]. constructor.
Qed.

Lemma cast_bool_of_int:
  forall b, sem_cast (int_of_bool b) (ct Pbool) = Some (of_bool b).
Proof. destruct b; reflexivity. Qed.

Lemma ev_cast_bool:
  forall a b, eval_expr ge [] le m a = Some (int_of_bool b) ->
  eval_expr ge [] le m (Ecast a (ct Pbool)) = Some (of_bool b).
Proof. intros a b H. cbn. rewrite H. apply cast_bool_of_int. Qed.

Lemma truth_ne0:
  forall qc vc, sig_prim qc = true -> prim_eqb qc Pbool = false -> typed vc qc ->
  sem_binop One (ct qc) vc (zero_of_prim qc) = Some (int_of_bool (truth vc)).
Proof.
  intros qc vc S B T. destruct qc; simpl in S, B; try discriminate; typed_inv; simpl.
  - unfold int_binop. rewrite (in_range_of_norm 32 Signed x) by (auto; lia). simpl.
    unfold truth; simpl. destruct (x =? 0); reflexivity.
  - unfold int_binop. rewrite (in_range_of_norm 32 Unsigned x) by (auto; lia). simpl.
    unfold truth; simpl. destruct (x =? 0); reflexivity.
  - unfold int_binop. rewrite (in_range_of_norm 64 Signed x) by (auto; lia). simpl.
    unfold truth; simpl. destruct (x =? 0); reflexivity.
  - unfold int_binop. rewrite (in_range_of_norm 64 Unsigned x) by (auto; lia). simpl.
    unfold truth; simpl. destruct (x =? 0); reflexivity.
  - destruct x as [[]|[]|[] pl Hp|[] mx ex Hx]; reflexivity.
  - destruct x as [[]|[]|[] pl Hp|[] mx ex Hx]; reflexivity.
Qed.

(** One equation: its statement sets the signal's temporary to the
    block's output, a value of the signal's type. *)
Lemma exec_eq:
  forall x q b, block_ok d (sig_type tctx) b q = true -> find_assoc x tctx = None ->
  exec_stmt ctx ge [] le m w (eq_stmt d (mkeq x q b)) []
            (set_assoc (temp_of x) (eval_block s u env b q) le) m w Out_normal
  /\ typed (eval_block s u env b q) q.
Proof.
  intros x q b OK X. unfold block_ok in OK. apply andb_true_iff in OK as [SQ OK].
  destruct b as [f|f|c|k a|terms|a b|a b|a|ismax args|lo hi a|op qa a b|op args|crit qc thr a c b];
    unfold eq_stmt; simpl eq_block; simpl eq_type; cbv zeta.
  - (* Binport *)
    destruct (find_assoc f (dg_inputs d)) as [q'|] eqn:F; [|discriminate].
    apply prim_eqb_true in OK; subst q'.
    destruct (Uty f q F) as [v [M T]].
    assert (E: field_val u f = v) by (unfold field_val; rewrite M; reflexivity).
    simpl. rewrite E. split; auto. apply exec_set. eapply ev_field; eauto.
  - (* Bstate *)
    destruct (state_type d f) as [q'|] eqn:F; [|discriminate].
    apply prim_eqb_true in OK; subst q'.
    destruct (state_type_In f q F) as [st [I [<- <-]]].
    destruct (Sty st I) as [v [M T]].
    destruct (HS (has_states_In st I)) as [FS GS].
    assert (E: field_val s (st_name st) = v) by (unfold field_val; rewrite M; reflexivity).
    simpl. rewrite E. split; auto. apply exec_set. eapply ev_field; eauto.
  - (* Bconst *)
    assert (T := val_of_prim_typed c q OK).
    simpl. split; auto. apply exec_set. apply ev_const; auto.
  - (* Bgain *)
    apply andb_true_iff in OK as [OK Fa]. apply andb_true_iff in OK as [N Kt].
    destruct (tmp_ok a q Fa) as [Ea Ta]. assert (Tk := val_of_prim_typed k q Kt).
    simpl. split; [|apply arith_typed; auto; left; discriminate].
    apply exec_set. apply ev_arith; auto;
      first [ left; discriminate | apply typeof_const | apply ev_const; auto ].
  - (* Bsum *)
    apply andb_true_iff in OK as [OK F]. apply andb_true_iff in OK as [N L].
    destruct terms as [|[p a] terms]; [discriminate|].
    simpl in F. apply andb_true_iff in F as [Fa F].
    destruct (tmp_ok a q Fa) as [Ea Ta].
    assert (A0: eval_expr ge [] le m (if p then tmp a q else neg_expr q (tmp a q))
                = Some (if p then sig env a else negate q (sig env a))
                /\ typed (if p then sig env a else negate q (sig env a)) q
                /\ typeof (if p then tmp a q else neg_expr q (tmp a q)) = ct q).
    { destruct p.
      - split; [exact Ea | split; [exact Ta | reflexivity]].
      - split; [apply ev_neg; auto | split; [apply negate_typed; auto | apply typeof_neg]]. }
    destruct A0 as [E0 [T0 Y0]].
    destruct (ev_sum q terms _ _ N F E0 T0 Y0) as [E T].
    simpl. split; auto. apply exec_set. exact E.
  - (* Bproduct *)
    apply andb_true_iff in OK as [OK Fb]. apply andb_true_iff in OK as [N Fa].
    destruct (tmp_ok a q Fa) as [Ea Ta]. destruct (tmp_ok b q Fb) as [Eb Tb].
    simpl. split; [|apply arith_typed; auto; left; discriminate].
    apply exec_set. apply ev_arith; auto. left; discriminate.
  - (* Bdivide *)
    apply andb_true_iff in OK as [OK Fb]. apply andb_true_iff in OK as [Fl Fa].
    assert (N: num_prim q = true) by (destruct q; simpl in Fl; try discriminate; reflexivity).
    destruct (tmp_ok a q Fa) as [Ea Ta]. destruct (tmp_ok b q Fb) as [Eb Tb].
    simpl. split; [|apply arith_typed; auto].
    apply exec_set. apply ev_arith; auto.
  - (* Babs *)
    apply andb_true_iff in OK as [Fl Fa].
    destruct (tmp_ok a q Fa) as [Ea Ta].
    destruct q; simpl in Fl; try discriminate;
      destruct (sig env a) eqn:SA; simpl in Ta; try contradiction; simpl; rewrite SA;
      (split; [apply exec_set; cbn; cbn in Ea; rewrite Ea; reflexivity | exact I]).
  - (* Bminmax *)
    apply andb_true_iff in OK as [OK F]. apply andb_true_iff in OK as [N L].
    destruct args as [|a args]; [discriminate|].
    simpl in F. apply andb_true_iff in F as [Fa F].
    destruct (tmp_ok a q Fa) as [Ea Ta].
    destruct (exec_minmax x q ismax args (sig env a) N F X Ta) as [E T].
    simpl. split; auto.
    eapply exec_seq; [apply exec_set; exact Ea | exact E].
  - (* Bsaturation *)
    apply andb_true_iff in OK as [OK Fa]. apply andb_true_iff in OK as [OK Th].
    apply andb_true_iff in OK as [N Tl].
    assert (TL := val_of_prim_typed lo q Tl). assert (TH := val_of_prim_typed hi q Th).
    assert (SP := SQ).
    destruct (tmp_ok a q Fa) as [Ea Ta].
    set (le1 := set_assoc (temp_of x) (sig env a) le).
    assert (Ex: eval_expr ge [] le1 m (Etempvar (temp_of x) (ct q)) = Some (sig env a))
      by (cbn; apply find_assoc_set_same).
    assert (Eh := ev_const ge le1 m hi q SP TH). assert (El := ev_const ge le1 m lo q SP TL).
    assert (C1 := ev_cmp ge le1 m Rgt q _ _ _ _ N Ex Eh Ta TH eq_refl (typeof_const hi q)).
    assert (C2 := ev_cmp ge le1 m Rlt q _ _ _ _ N Ex El Ta TL eq_refl (typeof_const lo q)).
    simpl. unfold saturate.
    split; [| destruct (compare Rgt q (sig env a) hi); [auto|]; destruct (compare Rlt q (sig env a) lo); auto].
    eapply exec_seq; [apply exec_set; exact Ea|]. fold le1.
    eapply exec_if; [exact C1 | apply bool_val_int_of_bool |].
    destruct (compare Rgt q (sig env a) hi).
    + unfold le1. rewrite <- (set_assoc_twice _ (temp_of x) hi (sig env a) le).
      apply exec_set. exact Eh.
    + eapply exec_if; [exact C2 | apply bool_val_int_of_bool |].
      destruct (compare Rlt q (sig env a) lo).
      * unfold le1. rewrite <- (set_assoc_twice _ (temp_of x) lo (sig env a) le).
        apply exec_set. exact El.
      * constructor.
  - (* Brelational *)
    apply andb_true_iff in OK as [OK Fb]. apply andb_true_iff in OK as [OK Fa].
    apply andb_true_iff in OK as [B N]. apply prim_eqb_true in B; subst q.
    destruct (tmp_ok a qa Fa) as [Ea Ta]. destruct (tmp_ok b qa Fb) as [Eb Tb].
    simpl. split; [|apply of_bool_typed].
    apply exec_set. apply ev_cast_bool. apply ev_cmp; auto.
  - (* Blogical *)
    apply andb_true_iff in OK as [OK Sh]. apply andb_true_iff in OK as [B F].
    apply prim_eqb_true in B; subst q.
    simpl. split; [|apply of_bool_typed].
    apply exec_set. apply ev_cast_bool. apply ev_logic.
    + clear Sh. induction args as [|a args IH]; simpl; constructor.
      * simpl in F. apply andb_true_iff in F as [Fa _].
        destruct (tmp_ok a Pbool Fa) as [Ea Ta]. split; [apply ev_truth; auto | reflexivity].
      * simpl in F. apply andb_true_iff in F as [_ F]. auto.
    + destruct op, args as [|a1 [|a2 args]]; simpl in Sh |- *; try discriminate; exact I.
  - (* Bswitch *)
    apply andb_true_iff in OK as [OK Cr]. apply andb_true_iff in OK as [OK Fc].
    apply andb_true_iff in OK as [Fa Fb].
    destruct (tmp_ok a q Fa) as [Ea Ta]. destruct (tmp_ok b q Fb) as [Eb Tb].
    destruct (tmp_ok c qc Fc) as [Ec Tc].
    assert (Cond: eval_expr ge [] le m (switch_cond crit qc thr (tmp c qc))
                  = Some (int_of_bool (match crit with
                                       | Cge => compare Rge qc (sig env c) thr
                                       | Cgt => compare Rgt qc (sig env c) thr
                                       | Cne0 => truth (sig env c)
                                       end))).
    { destruct crit; simpl.
      - apply andb_true_iff in Cr as [N Tt]. assert (TT := val_of_prim_typed thr qc Tt).
        apply ev_cmp; auto.
        + apply ev_const; auto. apply num_sig; auto.
        + apply typeof_const.
      - apply andb_true_iff in Cr as [N Tt]. assert (TT := val_of_prim_typed thr qc Tt).
        apply ev_cmp; auto.
        + apply ev_const; auto. apply num_sig; auto.
        + apply typeof_const.
      - destruct (prim_eqb qc Pbool) eqn:B.
        + apply prim_eqb_true in B; subst qc. apply ev_truth; auto.
        + cbn - [sem_binop]. unfold tmp in Ec. cbn in Ec. rewrite Ec.
          assert (Z: eval_expr ge [] le m (const_expr (zero_of_prim qc) qc) = Some (zero_of_prim qc)).
          { apply ev_const; auto. destruct qc; simpl in B, Cr |- *; try discriminate; reflexivity. }
          rewrite Z. rewrite typeof_const.
          assert (BT: binop_type One (ct qc) = Some tint).
          { unfold binop_type. destruct qc; simpl in Cr, B |- *; try discriminate; reflexivity. }
          rewrite BT, !type_eqb_refl. simpl.
          apply truth_ne0; auto. }
    simpl.
    destruct (match crit with
              | Cge => compare Rge qc (sig env c) thr
              | Cgt => compare Rgt qc (sig env c) thr
              | Cne0 => truth (sig env c)
              end) eqn:P;
      (split; [eapply exec_if; [exact Cond | apply bool_val_int_of_bool | apply exec_set; auto] | auto]).
Qed.

End BLOCK.

Lemma find_assoc_none_of_not_in:
  forall (A : Type) x (l : list (ident * A)), in_ident x (map fst l) = false -> find_assoc x l = None.
Proof.
  intros A x l H. destruct (find_assoc x l) eqn:F; auto.
  apply find_assoc_In in F. assert (I: In x (map fst l)) by (apply (in_map fst _ _ F)).
  apply in_ident_spec in I. congruence.
Qed.

(** The equations in order: the temporaries end holding every signal. *)
Lemma exec_eqs:
  forall eqs tctx env le tctx',
  eqs_ok d tctx eqs = Some tctx' -> temps_ok tctx env le ->
  exists le',
     exec_stmt ctx ge [] le m w (seq_list (map (eq_stmt d) eqs)) [] le' m w Out_normal
  /\ temps_ok tctx' (eval_eqs s u env eqs) le'.
Proof.
  induction eqs as [|[x q b] eqs IH]; intros tctx env le tctx' OK TOK; simpl in OK |- *.
  - inversion OK; subst. exists le; split; auto. constructor.
  - destruct (block_ok d (sig_type tctx) b q && negb (in_ident x (map fst tctx))) eqn:B; [|discriminate].
    apply andb_true_iff in B as [B N]. apply negb_true_iff in N.
    assert (X := find_assoc_none_of_not_in _ _ _ N).
    destruct (exec_eq tctx env le TOK x q b B X) as [E T].
    set (v := eval_block s u env b q) in *.
    assert (TOK': temps_ok ((x, q) :: tctx) ((x, v) :: env) (set_assoc (temp_of x) v le)).
    { intros y qy Fy. simpl in Fy. unfold sig; simpl.
      destruct (string_dec y x) as [->|NE].
      - inversion Fy; subst. rewrite find_assoc_set_same. split; auto.
      - rewrite find_assoc_set_other by (intros Ex; apply temp_of_inj in Ex; congruence).
        exact (TOK y qy Fy). }
    destruct (IH _ _ _ _ OK TOK') as [le' [E' T']].
    exists le'. split; auto. eapply exec_seq; eauto.
Qed.

(** ** Stores into a field of a global struct *)

(** The memory after storing [v] into field [f] of block [b]. *)
Definition store_field (mm : mem) (b : Values.block) (ty : type) (fs : list (ident * mval)) (f : ident) (v : val) : mem :=
  mkmem (pset b (ty, MVstruct (set_field f (MVscalar v) fs)) (mem_contents mm)) (mem_next mm).

Lemma get_store_field_same:
  forall mm b ty fs f v, get_block (store_field mm b ty fs f v) b = Some (ty, MVstruct (set_field f (MVscalar v) fs)).
Proof. intros; unfold store_field, get_block; simpl; apply pgss. Qed.

Lemma get_store_field_other:
  forall mm b ty fs f v b', b' <> b -> get_block (store_field mm b ty fs f v) b' = get_block mm b'.
Proof. intros; unfold store_field, get_block; simpl; apply pgso; auto. Qed.

Lemma exec_store_field:
  forall le mm X b sid ty fs f old e v q,
  find_var ge X = Some (b, Tstruct sid) -> get_block mm b = Some (ty, MVstruct fs) ->
  find_assoc f fs = Some old -> eval_expr ge [] le mm e = Some v -> typed v q ->
  exec_stmt ctx ge [] le mm w (Sassign (Efield (Evar X (Tstruct sid)) f (ct q)) e) []
            le (store_field mm b ty fs f v) w Out_normal.
Proof.
  intros le mm X b sid ty fs f old e v q F G O E T. constructor.
  unfold eval_assign. cbn - [store]. rewrite F.
  assert (NS: match ct q with Tstruct _ => False | _ => True end) by (destruct q; exact I).
  destruct (ct q) eqn:CQ; try contradiction;
    rewrite E; unfold store; rewrite <- CQ, sem_cast_same by exact T;
    unfold store_path; rewrite G; simpl; rewrite O; reflexivity.
Qed.

Lemma set_field_keeps:
  forall f g v fs, (exists o, find_assoc g fs = Some o) -> exists o', find_assoc g (set_field f v fs) = Some o'.
Proof.
  intros f g v fs [o H]. destruct (string_dec g f) as [->|N].
  - exists v. eapply find_assoc_set_field_same; eauto.
  - exists o. rewrite find_assoc_set_field_other; auto.
Qed.

(** Storing fields [l] in order into [fs] with the same names, each
    once, gives [l]. *)
Lemma fold_set_fields_skip:
  forall (l : list (ident * mval)) h rest, ~ In (fst h) (map fst l) ->
  fold_left (fun acc fv => set_field (fst fv) (snd fv) acc) l (h :: rest)
  = h :: fold_left (fun acc fv => set_field (fst fv) (snd fv) acc) l rest.
Proof.
  induction l as [|[f v] l IH]; intros [g o] rest N; simpl in *; auto.
  destruct (ident_eq f g) as [E|E]; [subst; tauto|].
  apply IH. simpl. tauto.
Qed.

Lemma fold_set_fields:
  forall (l : list (ident * mval)) fs, map fst l = map fst fs -> NoDup (map fst l) ->
  fold_left (fun acc fv => set_field (fst fv) (snd fv) acc) l fs = l.
Proof.
  induction l as [|[f v] l IH]; intros fs M N; destruct fs as [|[g o] fs]; simpl in *;
    try discriminate; auto.
  inversion M; subst g. inversion N as [|? ? NI N']; subst.
  destruct (ident_eq f f) as [_|E]; [|congruence].
  rewrite fold_set_fields_skip by (simpl; auto). f_equal. apply IH; auto.
Qed.

Section STORES.

Variables (tctx : list (ident * prim)) (env : senv) (le : temp_env).
Hypothesis TOK : temps_ok tctx env le.
Variables (by_ : Values.block) (tyY : type).
Hypothesis HY : find_var ge (dg_out_var d) = Some (by_, Tstruct (dg_out_struct d)).

Definition out_val (f : ident) : val :=
  match find_assoc f (dg_outs d) with Some x => sig env x | None => Vundef end.

Lemma exec_outs:
  forall L fs mm,
  get_block mm by_ = Some (tyY, MVstruct fs) ->
  (forall fq, In fq L -> exists o, find_assoc (fst fq) fs = Some o) ->
  (forall fq, In fq L -> exists x, find_assoc (fst fq) (dg_outs d) = Some x /\ has_type tctx x (snd fq) = true) ->
  exists mm',
     exec_stmt ctx ge [] le mm w (seq_list (map (out_stmt d) L)) [] le mm' w Out_normal
  /\ get_block mm' by_ = Some (tyY, MVstruct (fold_left (fun acc fv => set_field (fst fv) (snd fv) acc)
                                              (map (fun fq => (fst fq, MVscalar (out_val (fst fq)))) L) fs))
  /\ (forall b', b' <> by_ -> get_block mm' b' = get_block mm b')
  /\ mem_next mm' = mem_next mm.
Proof.
  induction L as [|[f q] L IH]; intros fs mm G Ex Src; simpl.
  - exists mm. repeat split; auto. constructor.
  - destruct (Ex (f, q) (or_introl eq_refl)) as [o O].
    destruct (Src (f, q) (or_introl eq_refl)) as [x [Fx Tx]]. simpl in Fx, Tx.
    destruct (tmp_ok tctx env le TOK x q Tx) as [E T].
    set (mm1 := store_field mm by_ tyY fs f (sig env x)).
    assert (E1: exec_stmt ctx ge [] le mm w (out_stmt d (f, q)) [] le mm1 w Out_normal).
    { unfold out_stmt. rewrite Fx. eapply exec_store_field; eauto. }
    destruct (IH (set_field f (MVscalar (sig env x)) fs) mm1) as [mm' [E' [G' [O' N']]]].
    + apply get_store_field_same.
    + intros fq I. apply set_field_keeps. apply Ex. simpl; auto.
    + intros fq I. apply Src. simpl; auto.
    + exists mm'. split; [eapply exec_seq; eauto|].
      assert (OV: out_val f = sig env x) by (unfold out_val; rewrite Fx; reflexivity).
      rewrite OV. split; [exact G'|]. split.
      * intros b' N. rewrite O' by auto. apply get_store_field_other; auto.
      * rewrite N'. reflexivity.
Qed.

End STORES.

Lemma set_field_twice:
  forall f v v' fs, set_field f v (set_field f v' fs) = set_field f v fs.
Proof.
  induction fs as [|[g o] fs IH]; simpl; auto.
  destruct (ident_eq f g) as [E|E]; simpl.
  - destruct (ident_eq f g); congruence.
  - destruct (ident_eq f g); [congruence|]. rewrite IH; reflexivity.
Qed.

Section STATES.

Variables (tctx : list (ident * prim)) (env : senv) (le : temp_env).
Hypothesis TOK : temps_ok tctx env le.
Hypothesis HSv : find_var ge (dg_state_var d) = Some (bs, Tstruct (dg_state_struct d)).
Variable tyS : type.

(** One state update, from a block whose member [st_name st] still
    holds the state's value in [s]. *)
Lemma exec_update:
  forall st fs mm, state_ok (sig_type tctx) st = true ->
  get_block mm bs = Some (tyS, MVstruct fs) ->
  find_assoc (st_name st) fs = Some (MVscalar (field_val s (st_name st))) ->
  typed (field_val s (st_name st)) (st_type st) ->
  exists mm',
     exec_stmt ctx ge [] le mm w (update_stmt d st) [] le mm' w Out_normal
  /\ get_block mm' bs = Some (tyS, MVstruct (set_field (st_name st) (MVscalar (next_state s env st)) fs))
  /\ (forall b', b' <> bs -> get_block mm' b' = get_block mm b')
  /\ mem_next mm' = mem_next mm.
Proof.
  intros [x q init inp kind] fs mm OK G O Tx. unfold state_ok in OK; simpl in *.
  apply andb_true_iff in OK as [OK K]. apply andb_true_iff in OK as [OK Fi].
  apply andb_true_iff in OK as [SQ Ti].
  destruct (tmp_ok tctx env le TOK inp q Fi) as [Ei TIi].
  unfold update_stmt, next_state, state_lv; simpl.
  destruct kind as [|kt lim].
  - exists (store_field mm bs tyS fs x (sig env inp)). split; [eapply exec_store_field; eauto|].
    split; [apply get_store_field_same|]. split; [intros; apply get_store_field_other; auto|reflexivity].
  - apply andb_true_iff in K as [K L]. apply andb_true_iff in K as [Fl Tk].
    assert (N: num_prim q = true) by (destruct q; simpl in Fl; try discriminate; reflexivity).
    assert (TK := val_of_prim_typed kt q Tk).
    set (xs := field_val s x) in *.
    set (y := arith Aadd q xs (arith Amul q kt (sig env inp))).
    assert (Ex: forall mm0 fs0, get_block mm0 bs = Some (tyS, MVstruct fs0) ->
                  find_assoc x fs0 = Some (MVscalar xs) ->
                  eval_expr ge [] le mm0 (Efield (Evar (dg_state_var d) (Tstruct (dg_state_struct d))) x (ct q))
                  = Some xs).
    { intros mm0 fs0 G0 O0. eapply ev_field_mem; eauto. simpl. rewrite O0. reflexivity. }
    assert (Ei': eval_expr ge [] le mm (tmp inp q) = Some (sig env inp))
      by (rewrite (tmp_any_mem le mm m); exact Ei).
    assert (Ey: eval_expr ge [] le mm (arith_expr Aadd q (Efield (Evar (dg_state_var d) (Tstruct (dg_state_struct d))) x (ct q))
                                         (arith_expr Amul q (const_expr kt q) (tmp inp q))) = Some y).
    { apply ev_arith; auto;
        first [ left; discriminate | apply typeof_arith | reflexivity | (eapply Ex; eauto)
              | (apply arith_typed; auto; left; discriminate)
              | (apply ev_arith; auto; first [left; discriminate | apply ev_const; auto | apply typeof_const]) ]. }
    assert (Ty: typed y q)
      by (apply arith_typed; auto; first [left; discriminate | apply arith_typed; auto; left; discriminate]).
    set (mm1 := store_field mm bs tyS fs x y).
    assert (E1 := exec_store_field le mm _ _ _ _ fs x _ _ y q HSv G O Ey Ty).
    destruct lim as [[lo hi]|].
    + apply andb_true_iff in L as [Tl Th].
      assert (TL := val_of_prim_typed lo q Tl). assert (TH := val_of_prim_typed hi q Th).
      assert (G1 := get_store_field_same mm bs tyS fs x y). fold mm1 in G1.
      assert (O1: find_assoc x (set_field x (MVscalar y) fs) = Some (MVscalar y))
        by (eapply find_assoc_set_field_same; eauto).
      assert (Ex1: eval_expr ge [] le mm1 (Efield (Evar (dg_state_var d) (Tstruct (dg_state_struct d))) x (ct q)) = Some y).
      { eapply ev_field_mem; eauto. simpl. rewrite O1. reflexivity. }
      assert (C1 := ev_cmp ge le mm1 Rgt q _ _ _ _ N Ex1 (ev_const ge le mm1 hi q SQ TH) Ty TH eq_refl (typeof_const hi q)).
      assert (C2 := ev_cmp ge le mm1 Rlt q _ _ _ _ N Ex1 (ev_const ge le mm1 lo q SQ TL) Ty TL eq_refl (typeof_const lo q)).
      unfold saturate. fold y.
      destruct (compare Rgt q y hi) eqn:CH.
      * exists (store_field mm1 bs tyS (set_field x (MVscalar y) fs) x hi).
        split; [eapply exec_seq; [exact E1|]; eapply exec_if; [exact C1 | apply bool_val_int_of_bool |];
                eapply exec_store_field; eauto; apply ev_const; auto|].
        rewrite get_store_field_same, set_field_twice. split; [reflexivity|].
        split; [intros; rewrite get_store_field_other by auto; apply get_store_field_other; auto | reflexivity].
      * destruct (compare Rlt q y lo) eqn:CL.
        -- exists (store_field mm1 bs tyS (set_field x (MVscalar y) fs) x lo).
           split; [eapply exec_seq; [exact E1|]; eapply exec_if; [exact C1 | apply bool_val_int_of_bool |];
                   eapply exec_if; [exact C2 | apply bool_val_int_of_bool |];
                   eapply exec_store_field; eauto; apply ev_const; auto|].
           rewrite get_store_field_same, set_field_twice. split; [reflexivity|].
           split; [intros; rewrite get_store_field_other by auto; apply get_store_field_other; auto | reflexivity].
        -- exists mm1.
           split; [eapply exec_seq; [exact E1|]; eapply exec_if; [exact C1 | apply bool_val_int_of_bool |];
                   eapply exec_if; [exact C2 | apply bool_val_int_of_bool |]; constructor|].
           split; [exact G1|]. split; [intros; apply get_store_field_other; auto | reflexivity].
    + exists mm1. split; [eapply exec_seq; [exact E1 | constructor]|].
      split; [apply get_store_field_same|]. split; [intros; apply get_store_field_other; auto|reflexivity].
Qed.

Lemma exec_states:
  forall L fs mm,
  (forall st, In st L -> state_ok (sig_type tctx) st = true) -> NoDup (map st_name L) ->
  get_block mm bs = Some (tyS, MVstruct fs) ->
  (forall st, In st L -> find_assoc (st_name st) fs = Some (MVscalar (field_val s (st_name st)))
                        /\ typed (field_val s (st_name st)) (st_type st)) ->
  exists mm',
     exec_stmt ctx ge [] le mm w (seq_list (map (update_stmt d) L)) [] le mm' w Out_normal
  /\ get_block mm' bs = Some (tyS, MVstruct (fold_left (fun acc fv => set_field (fst fv) (snd fv) acc)
                            (map (fun st => (st_name st, MVscalar (next_state s env st))) L) fs))
  /\ (forall b', b' <> bs -> get_block mm' b' = get_block mm b')
  /\ mem_next mm' = mem_next mm.
Proof.
  induction L as [|st L IH]; intros fs mm OK ND G V; simpl.
  - exists mm. repeat split; auto. constructor.
  - inversion ND as [|? ? NI ND']; subst.
    destruct (V st (or_introl eq_refl)) as [O T].
    destruct (exec_update st fs mm (OK st (or_introl eq_refl)) G O T) as [mm1 [E1 [G1 [U1 N1]]]].
    destruct (IH _ mm1 (fun st' I => OK st' (or_intror I)) ND' G1) as [mm' [E' [G' [U' N']]]].
    + intros st' I. destruct (V st' (or_intror I)) as [O' T']. split; auto.
      rewrite find_assoc_set_field_other; auto.
      intros Eq. apply NI. rewrite <- Eq. apply in_map; auto.
    + exists mm'. split; [eapply exec_seq; eauto|]. split; [exact G'|].
      split; [intros; rewrite U', U1; auto | congruence].
Qed.

End STATES.

(** ** The step function *)

Section CALL.

Variables (by_ : Values.block) (tyY tyS : type) (fsY sfs : list (ident * mval)).
Hypothesis WF : dg_wf d = true.
Hypothesis HY : find_var ge (dg_out_var d) = Some (by_, Tstruct (dg_out_struct d)).
Hypothesis GY : get_block m by_ = Some (tyY, MVstruct fsY).
Hypothesis NY : map fst fsY = map fst (dg_outputs d).
Hypothesis GS : has_states d = true -> get_block m bs = Some (tyS, s).
Hypothesis SF : s = MVstruct sfs.
Hypothesis NS : map fst sfs = map st_name (dg_states d).
Hypothesis DYS : has_states d = true -> by_ <> bs.

Lemma dg_wf_inv:
  exists tctx, eqs_ok d [] (dg_eqs d) = Some tctx
  /\ forallb (state_ok (sig_type tctx)) (dg_states d) = true /\ outs_ok d (sig_type tctx) = true
  /\ NoDup (map st_name (dg_states d)) /\ NoDup (map fst (dg_outputs d)).
Proof.
  unfold dg_wf, wf_rest in WF. destruct (eqs_ok d [] (dg_eqs d)) as [tctx|] eqn:EQ; [|discriminate].
  exists tctx. split; auto.
  apply andb_true_iff in WF as [WF _]. apply andb_true_iff in WF as [WF _].
  apply andb_true_iff in WF as [WF _]. apply andb_true_iff in WF as [WF _].
  apply andb_true_iff in WF as [WF _]. apply andb_true_iff in WF as [WF _].
  apply andb_true_iff in WF as [WF No]. apply andb_true_iff in WF as [WF _].
  apply andb_true_iff in WF as [WF Ns]. apply andb_true_iff in WF as [Fs Oo].
  apply nodup_idents_spec in No. apply nodup_idents_spec in Ns. tauto.
Qed.

Lemma step_call:
  exists m',
     eval_funcall ctx ge m w (Internal (step_function d)) [] [] m' w Vundef
  /\ get_block m' by_ = Some (tyY, snd (dg_step d s u))
  /\ (has_states d = true -> get_block m' bs = Some (tyS, fst (dg_step d s u)))
  /\ (forall b', b' <> by_ -> (has_states d = true -> b' <> bs) -> get_block m' b' = get_block m b')
  /\ mem_next m' = mem_next m.
Proof.
  destruct dg_wf_inv as [tctx [EQ [FS [OO [NDS NDO]]]]].
  set (le0 := create_undef_temps (map (fun e => (temp_of (eq_sig e), ct (eq_type e))) (dg_eqs d))).
  assert (T0: temps_ok [] [] le0) by (intros x q F; discriminate).
  destruct (exec_eqs (dg_eqs d) [] [] le0 tctx EQ T0) as [le1 [E1 T1]].
  set (env := eval_eqs s u [] (dg_eqs d)) in T1.
  (* the outputs *)
  destruct (exec_outs tctx env le1 T1 by_ tyY HY (dg_outputs d) fsY m GY) as [m2 [E2 [G2 [U2 N2]]]].
  { intros fq I. assert (IF: In (fst fq) (map fst fsY)) by (rewrite NY; apply in_map; auto).
    apply in_map_iff in IF as [[f o] [Ef If]]. simpl in Ef; subst f. exists o.
    apply In_find_assoc; auto. rewrite NY. exact NDO. }
  { intros fq I. unfold outs_ok in OO.
    apply andb_true_iff in OO as [_ OO]. rewrite forallb_forall in OO. specialize (OO fq I).
    destruct (find_assoc (fst fq) (dg_outs d)) as [x|]; [eauto | discriminate]. }
  (* the states *)
  assert (ST: exists m3,
     exec_stmt ctx ge [] le1 m2 w (seq_list (map (update_stmt d) (dg_states d))) [] le1 m3 w Out_normal
  /\ (has_states d = true -> get_block m3 bs = Some (tyS, state_value d (next_state s env)))
  /\ (forall b', (has_states d = true -> b' <> bs) -> get_block m3 b' = get_block m2 b')
  /\ mem_next m3 = mem_next m2).
  { destruct (has_states d) eqn:H.
    - destruct (HS eq_refl) as [HSv _].
      assert (G2S: get_block m2 bs = Some (tyS, MVstruct sfs)).
      { rewrite U2 by (apply not_eq_sym; apply DYS; auto). rewrite <- SF. apply GS; auto. }
      destruct (exec_states tctx env le1 T1 HSv tyS (dg_states d) sfs m2) as [m3 [E3 [G3 [U3 N3]]]]; auto.
      + intros st I. rewrite forallb_forall in FS. auto.
      + intros st I. destruct (Sty st I) as [v [M T]].
        assert (FV: field_val s (st_name st) = v) by (unfold field_val; rewrite M; reflexivity).
        rewrite FV. split; auto. rewrite SF in M. simpl in M.
        destruct (find_assoc (st_name st) sfs) as [[]|]; simpl in M; congruence.
      + exists m3. split; [exact E3|]. split; [|split; [intros b' Nb; apply U3; auto | exact N3]].
        intros _. rewrite G3. f_equal. f_equal. unfold state_value. f_equal.
        apply fold_set_fields.
        * rewrite map_map. simpl. rewrite NS. reflexivity.
        * rewrite map_map. simpl. exact NDS.
    - unfold has_states in H. apply negb_false_iff in H. apply Nat.eqb_eq in H.
      destruct (dg_states d); [|discriminate]. simpl.
      exists m2. split; [constructor|]. split; [discriminate|]. split; auto. }
  destruct ST as [m3 [E3 [G3 [U3 N3]]]].
  exists m3. split.
  - change m3 with (free_vars m3 []). eapply eval_funcall_internal.
    + unfold function_entry. simpl. reflexivity.
    + eapply exec_seq; [exact E1|]. eapply exec_seq; [exact E2 | exact E3].
    + reflexivity.
  - unfold dg_step. fold env. simpl. split; [|split; [exact G3|split]].
    + rewrite U3 by (intros H; apply DYS; auto). rewrite G2.
      f_equal. f_equal. unfold output_value. f_equal.
      apply fold_set_fields.
      * rewrite map_map. simpl. rewrite NY. reflexivity.
      * rewrite map_map. simpl. exact NDO.
    + intros b' N1 N2'. rewrite U3 by auto. apply U2; auto.
    + congruence.
Qed.

(** [Controller_initialize]: every state member gets its initial value. *)
Lemma exec_inits:
  forall L fs mm le,
  find_var ge (dg_state_var d) = Some (bs, Tstruct (dg_state_struct d)) ->
  (forall st, In st L -> sig_prim (st_type st) = true /\ typed (st_init st) (st_type st)) ->
  get_block mm bs = Some (tyS, MVstruct fs) ->
  (forall st, In st L -> exists o, find_assoc (st_name st) fs = Some o) ->
  exists mm',
     exec_stmt ctx ge [] le mm w
       (seq_list (map (fun st => Sassign (state_lv d st) (const_expr (st_init st) (st_type st))) L))
       [] le mm' w Out_normal
  /\ get_block mm' bs = Some (tyS, MVstruct (fold_left (fun acc fv => set_field (fst fv) (snd fv) acc)
                            (map (fun st => (st_name st, MVscalar (st_init st))) L) fs))
  /\ (forall b', b' <> bs -> get_block mm' b' = get_block mm b')
  /\ mem_next mm' = mem_next mm.
Proof.
  induction L as [|st L IH]; intros fs mm le HSv T G V; simpl.
  - exists mm. repeat split; auto. constructor.
  - destruct (T st (or_introl eq_refl)) as [SP TI]. destruct (V st (or_introl eq_refl)) as [o O].
    set (mm1 := store_field mm bs tyS fs (st_name st) (st_init st)).
    assert (E1: exec_stmt ctx ge [] le mm w (Sassign (state_lv d st) (const_expr (st_init st) (st_type st)))
                          [] le mm1 w Out_normal).
    { unfold state_lv. eapply exec_store_field; eauto. apply ev_const; auto. }
    destruct (IH (set_field (st_name st) (MVscalar (st_init st)) fs) mm1 le HSv) as [mm' [E' [G' [U' N']]]].
    + intros; apply T; simpl; auto.
    + apply get_store_field_same.
    + intros st' I. apply set_field_keeps. apply V. simpl; auto.
    + exists mm'. split; [eapply exec_seq; eauto|]. split; [exact G'|].
      split; [intros; rewrite U' by auto; apply get_store_field_other; auto | rewrite N'; reflexivity].
Qed.

Lemma init_call:
  forall sfs0, has_states d = true -> get_block m bs = Some (tyS, MVstruct sfs0) ->
  map fst sfs0 = map st_name (dg_states d) ->
  exists m',
     eval_funcall ctx ge m w (Internal (init_function d)) [] [] m' w Vundef
  /\ get_block m' bs = Some (tyS, dg_init d)
  /\ (forall b', b' <> bs -> get_block m' b' = get_block m b')
  /\ mem_next m' = mem_next m.
Proof.
  intros sfs0 H G N. destruct dg_wf_inv as [tctx [EQ [FS [OO [NDS NDO]]]]].
  destruct (HS H) as [HSv _].
  destruct (exec_inits (dg_states d) sfs0 m [] HSv) as [m' [E' [G' [U' N']]]]; auto.
  - intros st I. rewrite forallb_forall in FS. specialize (FS st I). unfold state_ok in FS.
    repeat (apply andb_true_iff in FS as [FS ?]). split; auto. apply val_of_prim_typed; auto.
  - intros st I. assert (IN: In (st_name st) (map fst sfs0)) by (rewrite N; apply in_map; auto).
    apply in_map_iff in IN as [[f o] [Ef If]]. simpl in Ef; subst f. exists o.
    apply In_find_assoc; auto. rewrite N; auto.
  - exists m'. split; [|split; [|split; auto]].
    + change m' with (free_vars m' []). eapply eval_funcall_internal.
      * unfold function_entry. simpl. reflexivity.
      * exact E'.
      * reflexivity.
    + rewrite G'. unfold dg_init, state_value. do 3 f_equal. apply fold_set_fields.
      * rewrite map_map; simpl. rewrite N; reflexivity.
      * rewrite map_map; simpl. exact NDS.
Qed.

End CALL.

End STMT.
