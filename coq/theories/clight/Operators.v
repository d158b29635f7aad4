(** * The meaning of the arithmetic operators *)

(** [sem_unop] and [sem_binop] give the value of [op v] and [v1 op v2]
    for operands of type [ty], as C11 on an LP64 target with IEEE 754
    arithmetic (x86-64, gcc) computes it; [None] is undefined behaviour.

    The typing rules ([unop_type], [binop_type], used by [Typing] and by
    the semantics itself) only allow operand types that C's integer
    promotions and usual arithmetic conversions leave unchanged: [int],
    [unsigned int], [long long], [unsigned long long], [float], [double],
    the two operands of a binary operator having the same type.  So
    there is no implicit conversion to model, and the printed C computes
    in the type the AST says (the printer validation checks the C types
    of every printed operation, [pyrosgen/verify/printer_c.py]).

    Integers (C11 6.5.5-6.5.10): signed [+ - * /] whose mathematical
    result does not fit the type are undefined ([INT_MIN / -1] too), and
    so is [%] when the quotient does not fit; division and remainder by
    zero are undefined; [/] rounds toward zero ([Z.quot]), [%] is the
    matching remainder ([Z.rem]); unsigned arithmetic wraps modulo
    [2^bits]; [& | ^] act on two's complement bits; comparisons compare
    the values and give the [int] 1 or 0.

    Floats: [+ - * /] are [FloatOps] (round to nearest even, computed
    without axioms by Coq's [SpecFloat]); comparisons are [SpecFloat]'s
    [SFcompare] (a NaN is unordered: every comparison but [!=] is 0, and
    [+0 == -0]); [-x] flips the sign bit and [fabs] clears it, NaNs
    included, as gcc's [xorpd]/[andpd] do.  NaN *payloads* of [+ - * /]
    are [FloatOps]' choice (x86-64's: the first NaN operand, quieted);
    C leaves them unspecified and gcc may swap the operands of [+] and
    [*], so comparisons with compiled code only require a NaN where the
    semantics gives a NaN.  [%], [& | ^] are not defined on floats.

    [!v] is 1 when [v] is zero ([bool_val v = Some false]), else 0. *)

From Coq Require Import String List ZArith Bool Lia.
From Coq Require Import Floats.SpecFloat.
From Flocq Require Import IEEE754.Binary.
From ROSGen Require Import FloatOps Syntax Values.
Local Open Scope Z_scope.

(** ** Types *)

(** The operand types of the arithmetic operators. *)
Definition arith_type (ty : type) : bool :=
  match ty with
  | Tint I32 _ | Tlong _ | Tfloat _ => true
  | _ => false
  end.

Definition is_comparison (op : binary_operation) : bool :=
  match op with
  | Oeq | One | Olt | Ogt | Ole | Oge => true
  | _ => false
  end.

(** The type of [op e] for [e] of type [ty], if the subset allows it. *)
Definition unop_type (op : unary_operation) (ty : type) : option type :=
  match op, ty with
  | Oabsfloat, Tfloat _ => Some ty
  | Oabsfloat, _ => None
  | Oneg, _ => if arith_type ty then Some ty else None
  | Onotbool, _ => if arith_type ty then Some tint else None
  end.

(** The type of [e1 op e2] for [e1], [e2] of type [ty]. *)
Definition binop_type (op : binary_operation) (ty : type) : option type :=
  if arith_type ty then
    if is_comparison op then Some tint
    else match op, ty with
         | (Omod | Oand | Oor | Oxor), Tfloat _ => None
         | _, _ => Some ty
         end
  else None.

(** ** Integers *)

(** The range of an integer type of [bits] bits. *)
Definition int_min (bits : Z) (sg : signedness) : Z :=
  match sg with Signed => - 2 ^ (bits - 1) | Unsigned => 0 end.
Definition int_max (bits : Z) (sg : signedness) : Z :=
  match sg with Signed => 2 ^ (bits - 1) - 1 | Unsigned => 2 ^ bits - 1 end.

Definition in_range (bits : Z) (sg : signedness) (n : Z) : bool :=
  (int_min bits sg <=? n) && (n <=? int_max bits sg).

(** The result [r] of an arithmetic operation as a value of the type:
    unsigned arithmetic wraps, a signed result out of range is undefined. *)
Definition int_result (bits : Z) (sg : signedness) (r : Z) : option Z :=
  match sg with
  | Signed => if in_range bits Signed r then Some r else None
  | Unsigned => Some (wrap_unsigned bits r)
  end.

Definition int_of_bool (b : bool) : val := Vint (if b then 1 else 0).

(** [n1 op n2] on an integer type of [bits] bits; operands out of the
    type's range (ill-formed values) are undefined too. *)
Definition int_binop (bits : Z) (sg : signedness) (op : binary_operation) (n1 n2 : Z)
  : option (Z + bool) :=
  if negb (in_range bits sg n1 && in_range bits sg n2) then None else
  match op with
  | Oadd => option_map inl (int_result bits sg (n1 + n2))
  | Osub => option_map inl (int_result bits sg (n1 - n2))
  | Omul => option_map inl (int_result bits sg (n1 * n2))
  | Odiv => if n2 =? 0 then None else option_map inl (int_result bits sg (Z.quot n1 n2))
  | Omod =>
      if n2 =? 0 then None else
      match int_result bits sg (Z.quot n1 n2) with
      | Some _ => Some (inl (wrap bits sg (Z.rem n1 n2)))
      | None => None
      end
  (* [wrap] is the identity on these results (two's complement bits of
     values in range, a remainder smaller than the divisor); it is there
     so that [int_binop_norm] needs no bit-level argument *)
  | Oand => Some (inl (wrap bits sg (Z.land n1 n2)))
  | Oor => Some (inl (wrap bits sg (Z.lor n1 n2)))
  | Oxor => Some (inl (wrap bits sg (Z.lxor n1 n2)))
  | Oeq => Some (inr (n1 =? n2))
  | One => Some (inr (negb (n1 =? n2)))
  | Olt => Some (inr (n1 <? n2))
  | Ogt => Some (inr (n2 <? n1))
  | Ole => Some (inr (n1 <=? n2))
  | Oge => Some (inr (n2 <=? n1))
  end.

(** ** Floats *)

Section FLOAT.

Variables prec emax : Z.
Local Notation float := (binary_float prec emax).

(** The sign bit flipped, resp. cleared. *)
Definition fneg (x : float) : float :=
  match x with
  | B754_zero _ _ s => B754_zero _ _ (negb s)
  | B754_infinity _ _ s => B754_infinity _ _ (negb s)
  | B754_nan _ _ s pl H => B754_nan _ _ (negb s) pl H
  | B754_finite _ _ s m e H => B754_finite _ _ (negb s) m e H
  end.

Definition fabs (x : float) : float :=
  match x with
  | B754_zero _ _ _ => B754_zero _ _ false
  | B754_infinity _ _ _ => B754_infinity _ _ false
  | B754_nan _ _ _ pl H => B754_nan _ _ false pl H
  | B754_finite _ _ _ m e H => B754_finite _ _ false m e H
  end.

(** A comparison, from [SpecFloat]'s [SFcompare] ([None]: unordered). *)
Definition fcmp (op : binary_operation) (x y : float) : bool :=
  match op, SFcompare (B2SF prec emax x) (B2SF prec emax y) with
  | Oeq, Some Eq => true
  | One, Some Eq => false
  | One, _ => true
  | Olt, Some Lt => true
  | Ogt, Some Gt => true
  | Ole, Some (Lt | Eq) => true
  | Oge, Some (Gt | Eq) => true
  | _, _ => false
  end.

End FLOAT.

(** [x op y] on floats: a float, a truth value, or undefined. *)
Definition float_binop {F : Type} (add sub mul div : F -> F -> F) (cmp : binary_operation -> F -> F -> bool)
                       (op : binary_operation) (x y : F) : option (F + bool) :=
  match op with
  | Oadd => Some (inl (add x y))
  | Osub => Some (inl (sub x y))
  | Omul => Some (inl (mul x y))
  | Odiv => Some (inl (div x y))
  | Omod | Oand | Oor | Oxor => None
  | Oeq | One | Olt | Ogt | Ole | Oge => Some (inr (cmp op x y))
  end.

(** ** The operators *)

(** The value of an operation's result: a number of the operands' kind
    ([mk]), or the [int] 0 or 1 of a comparison. *)
Definition result_val {A : Type} (mk : A -> val) (r : option (A + bool)) : option val :=
  match r with
  | Some (inl x) => Some (mk x)
  | Some (inr b) => Some (int_of_bool b)
  | None => None
  end.

(** [e1 op e2] for operands of type [ty] with values [v1], [v2]. *)
Definition sem_binop (op : binary_operation) (ty : type) (v1 v2 : val) : option val :=
  match ty, v1, v2 with
  | Tint I32 sg, Vint n1, Vint n2 => result_val Vint (int_binop 32 sg op n1 n2)
  | Tlong sg, Vlong n1, Vlong n2 => result_val Vlong (int_binop 64 sg op n1 n2)
  | Tfloat F64, Vfloat x, Vfloat y =>
      result_val Vfloat (float_binop add64 sub64 mul64 div64 (fcmp 53 1024) op x y)
  | Tfloat F32, Vsingle x, Vsingle y =>
      result_val Vsingle (float_binop add32 sub32 mul32 div32 (fcmp 24 128) op x y)
  | _, _, _ => None
  end.

(** [op e] for an operand of type [ty] with value [v]. *)
Definition sem_unop (op : unary_operation) (ty : type) (v : val) : option val :=
  match op, ty, v with
  | Oneg, Tint I32 sg, Vint n =>
      if in_range 32 sg n then option_map Vint (int_result 32 sg (- n)) else None
  | Oneg, Tlong sg, Vlong n =>
      if in_range 64 sg n then option_map Vlong (int_result 64 sg (- n)) else None
  | Oneg, Tfloat F64, Vfloat x => Some (Vfloat (fneg 53 1024 x))
  | Oneg, Tfloat F32, Vsingle x => Some (Vsingle (fneg 24 128 x))
  | Oabsfloat, Tfloat F64, Vfloat x => Some (Vfloat (fabs 53 1024 x))
  | Oabsfloat, Tfloat F32, Vsingle x => Some (Vsingle (fabs 24 128 x))
  | Onotbool, (Tint I32 _ | Tlong _ | Tfloat _), _ =>
      if val_has_typeb v ty then
        match bool_val v with
        | Some b => Some (int_of_bool (negb b))
        | None => None
        end
      else None
  | _, _, _ => None
  end.

(** ** Results have the announced type *)

Lemma in_range_norm:
  forall bits sg n, 0 < bits -> in_range bits sg n = true -> wrap bits sg n = n.
Proof.
  intros bits sg n Hb H. unfold in_range, int_min, int_max in H.
  apply andb_true_iff in H as [H1 H2]. apply Z.leb_le in H1. apply Z.leb_le in H2.
  assert (Hhalf: 2 ^ bits = 2 * 2 ^ (bits - 1)).
  { replace bits with (Z.succ (bits - 1)) at 1 by lia. apply Z.pow_succ_r. lia. }
  assert (0 < 2 ^ (bits - 1)) by (apply Z.pow_pos_nonneg; lia).
  destruct sg; unfold wrap, wrap_signed, wrap_unsigned.
  - destruct (Z.le_gt_cases 0 n).
    + rewrite Z.mod_small by lia. destruct (n <? 2 ^ (bits - 1)) eqn:E; auto.
      apply Z.ltb_ge in E. lia.
    + replace (n mod 2 ^ bits) with (n + 2 ^ bits).
      * destruct (n + 2 ^ bits <? 2 ^ (bits - 1)) eqn:E; [apply Z.ltb_lt in E; lia | lia].
      * rewrite <- (Z.mod_small (n + 2 ^ bits) (2 ^ bits)) by lia.
        replace (n + 2 ^ bits) with (n + 1 * 2 ^ bits) by lia. rewrite Z.mod_add by lia.
        reflexivity.
  - apply Z.mod_small. lia.
Qed.

Lemma int_result_norm:
  forall bits sg r r', 0 < bits -> int_result bits sg r = Some r' -> wrap bits sg r' = r'.
Proof.
  intros bits sg r r' Hb H. destruct sg; simpl in H.
  - destruct (in_range bits Signed r) eqn:E; inversion H; subst. apply in_range_norm; auto.
  - inversion H; subst. unfold wrap. apply Z.mod_mod. apply Z.pow_nonzero; lia.
Qed.

Lemma int_of_bool_type: forall b, val_has_type (int_of_bool b) tint.
Proof. destruct b; reflexivity. Qed.

Lemma int_binop_norm:
  forall bits sg op n1 n2 r, 0 < bits ->
  int_binop bits sg op n1 n2 = Some (inl r) -> wrap bits sg r = r.
Proof.
  intros bits sg op n1 n2 r Hb H. unfold int_binop in H.
  destruct (negb _); [discriminate|].
  destruct op; try (destruct (n2 =? 0); [discriminate|]);
    try (destruct (int_result bits sg _) eqn:E; simpl in H; inversion H; subst;
         eapply int_result_norm; eauto; fail);
    try (destruct (int_result bits sg (Z.quot n1 n2)); inversion H; subst);
    inversion H; subst; apply wrap_idem; auto.
Qed.

(** What an operation computes has the type [binop_type] / [unop_type]
    announces. *)
Lemma sem_binop_type:
  forall op ty v1 v2 v ty',
  sem_binop op ty v1 v2 = Some v -> binop_type op ty = Some ty' -> val_has_type v ty'.
Proof.
  intros op ty v1 v2 v ty' H T.
  unfold binop_type in T. destruct (arith_type ty) eqn:A; [|discriminate].
  destruct ty as [| [| |] sg | sg | [|] | | | | ]; simpl in A; try discriminate;
    destruct v1; try discriminate; destruct v2; try discriminate; simpl in H.
  - destruct (int_binop 32 sg op n n0) as [[r|b]|] eqn:E; inversion H; subst.
    + assert (N := int_binop_norm 32 sg op n n0 r ltac:(lia) E).
      destruct op; simpl in T; inversion T; subst; try exact N;
        unfold int_binop in E; destruct (negb _); try discriminate;
        simpl in E; discriminate.
    + destruct op; simpl in T; inversion T; subst; try apply int_of_bool_type;
        unfold int_binop in E; destruct (negb _); try discriminate; simpl in E;
        repeat match goal with H : context [if ?c then _ else _] |- _ => destruct c end;
        try destruct (int_result _ _ _); simpl in E; discriminate.
  - destruct (int_binop 64 sg op n n0) as [[r|b]|] eqn:E; inversion H; subst.
    + assert (N := int_binop_norm 64 sg op n n0 r ltac:(lia) E).
      destruct op; simpl in T; inversion T; subst; try exact N;
        unfold int_binop in E; destruct (negb _); try discriminate;
        simpl in E; discriminate.
    + destruct op; simpl in T; inversion T; subst; try apply int_of_bool_type;
        unfold int_binop in E; destruct (negb _); try discriminate; simpl in E;
        repeat match goal with H : context [if ?c then _ else _] |- _ => destruct c end;
        try destruct (int_result _ _ _); simpl in E; discriminate.
  - destruct op; simpl in H, T; inversion H; inversion T; subst; try exact I;
      apply int_of_bool_type.
  - destruct op; simpl in H, T; inversion H; inversion T; subst; try exact I;
      apply int_of_bool_type.
Qed.

Lemma sem_unop_type:
  forall op ty v r ty',
  sem_unop op ty v = Some r -> unop_type op ty = Some ty' -> val_has_type r ty'.
Proof.
  intros op ty v r ty' H T.
  destruct op.
  - destruct ty as [| [| |] sg | sg | [|] | | | | ]; simpl in T; try discriminate;
      inversion T; subst; destruct v; simpl in H; try discriminate;
      try (inversion H; subst; exact I).
    + destruct (in_range 32 sg n); [|discriminate].
      destruct (int_result 32 sg (- n)) eqn:E; inversion H; subst.
      exact (int_result_norm 32 sg _ _ ltac:(lia) E).
    + destruct (in_range 64 sg n); [|discriminate].
      destruct (int_result 64 sg (- n)) eqn:E; inversion H; subst.
      exact (int_result_norm 64 sg _ _ ltac:(lia) E).
  - assert (ty' = tint) as -> by
      (destruct ty as [| [| |] sg | sg | [|] | | | | ]; simpl in T; congruence).
    assert (G: forall b, Some (int_of_bool b) = Some r -> val_has_type r tint)
      by (intros b E; inversion E; apply int_of_bool_type).
    unfold sem_unop in H.
    destruct ty as [| [| |] sg | sg | [|] | | | | ]; simpl in T; try discriminate;
      destruct (val_has_typeb v _); try discriminate;
      destruct (bool_val v); try discriminate; eapply G; eauto.
  - destruct ty as [| [| |] sg | sg | [|] | | | | ]; simpl in T; try discriminate;
      inversion T; subst; destruct v; simpl in H; try discriminate;
      inversion H; subst; exact I.
Qed.
