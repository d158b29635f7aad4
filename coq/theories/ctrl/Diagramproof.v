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
From ROSGen Require Import FloatOps Syntax Values Operators Memory Environment Semantics
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
    try reflexivity; congruence.
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
