(** * IEEE 754 bit patterns, without axioms *)

(** Conversions between the bit pattern of an IEEE 754 number (a [Z] [z] with
    [0 <= z < 2^(mw+ew+1)]) and Flocq's [binary_float].

    Flocq's own [b64_of_bits] / [b32_of_bits] build the validity proof of
    the float with real-number lemmas, which pulls Coq's classical reals
    (and their axioms) into anything that mentions them.  Here the decoder is
    written anew: it splits the pattern with Flocq's [split_bits] (plain
    integer arithmetic) and obtains the proof that the result is a valid
    float by computing the boolean check ([bounded], [nan_pl]) and matching
    on its value; the impossible [false] branches return a zero.  The other
    direction is Flocq's [bits_of_binary_float], which is closed.

    Main results, both closed under the global context:
    - [bits_of_float64_of_bits]: [bits_of_b64 (float64_of_bits z) = z] for
      every [z] with [0 <= z < 2^64] (NaN payloads included, no caveat);
    - [float64_of_bits_of_float64]: [float64_of_bits (bits_of_b64 f) = f]
      for every [f];
    and the same for binary32. *)

From Coq Require Import ZArith Bool Lia Eqdep_dec.
From Flocq Require Import Core.Zaux IEEE754.Binary IEEE754.Bits.

(** The two formats, as [ROSGen.Syntax] names them ([float64] for
    [double], [float32] for [float]); local names, so that this file does
    not depend on the C syntax. *)
Local Notation float64 := (binary_float 53 1024).
Local Notation float32 := (binary_float 24 128).

Local Open Scope Z_scope.

(** ** Number of binary digits *)

(** Flocq's [digits2_pos] is [Pos.size]; the two lemmas below are all we
    need of it, proved with integer arithmetic only. *)
Lemma digits2_pos_size: forall p, SpecFloat.digits2_pos p = Pos.size p.
Proof.
  induction p as [p IH|p IH|]; simpl; try rewrite IH; reflexivity.
Qed.

(** A positive below [2^n] has at most [n] digits. *)
Lemma digits2_pos_le:
  forall p n, 0 <= n -> Zpos p < 2 ^ n -> Zpos (SpecFloat.digits2_pos p) <= n.
Proof.
  intros p n Hn Hp. rewrite digits2_pos_size.
  assert (H: 2 ^ Zpos (Pos.size p) <= 2 * Zpos p).
  { generalize (Pos.size_le p); intros H.
    change (Zpos (2 ^ Pos.size p) <= Zpos (p~0)) in H.
    rewrite Pos2Z.inj_pow in H. change (Zpos p~0) with (2 * Zpos p) in H. lia. }
  assert (H2: 2 ^ Zpos (Pos.size p) < 2 ^ (n + 1)).
  { rewrite Z.pow_add_r by lia. lia. }
  apply Z.pow_lt_mono_r_iff in H2; lia.
Qed.

(** A positive at least [2^n] has more than [n] digits. *)
Lemma digits2_pos_gt:
  forall p n, 0 <= n -> 2 ^ n <= Zpos p -> n < Zpos (SpecFloat.digits2_pos p).
Proof.
  intros p n Hn Hp. rewrite digits2_pos_size.
  generalize (Pos.size_gt p); intros H.
  change (Zpos p < Zpos (2 ^ Pos.size p)) in H. rewrite Pos2Z.inj_pow in H.
  assert (H2: 2 ^ n < 2 ^ Zpos (Pos.size p)) by lia.
  apply Z.pow_lt_mono_r_iff in H2; lia.
Qed.

(** Two proofs of a boolean equation are equal (decidable UIP, no axiom). *)
Lemma bool_eq_proof_irrel: forall (b c : bool) (H1 H2 : b = c), H1 = H2.
Proof.
  intros. apply UIP_dec. exact Bool.bool_dec.
Qed.

(** ** The generic decoder *)

Section OF_BITS.

(** [mw] bits of fraction, [ew] bits of exponent. *)
Variables mw ew : Z.

Local Notation prec := (mw + 1).
Local Notation emax := (2 ^ (ew - 1)).
Local Notation emin := (SpecFloat.emin prec emax).
Local Notation float := (binary_float prec emax).

(** A finite float, when [(m, e)] is in range; [+0]/[-0] otherwise. *)
Definition mk_finite (s : bool) (m : positive) (e : Z) : float :=
  match SpecFloat.bounded prec emax m e as b
        return SpecFloat.bounded prec emax m e = b -> float with
  | true => fun H => B754_finite prec emax s m e H
  | false => fun _ => B754_zero prec emax s
  end eq_refl.

(** A NaN with payload [pl], when the payload fits; a zero otherwise. *)
Definition mk_nan (s : bool) (pl : positive) : float :=
  match nan_pl prec pl as b return nan_pl prec pl = b -> float with
  | true => fun H => B754_nan prec emax s pl H
  | false => fun _ => B754_zero prec emax s
  end eq_refl.

(** Decoding a bit pattern: sign, biased exponent, fraction. *)
Definition float_of_bits (x : Z) : float :=
  let '(s, m, e) := split_bits mw ew x in
  if Z.eqb e 0 then
    match m with
    | Zpos p => mk_finite s p emin                  (**r subnormal *)
    | _ => B754_zero prec emax s                    (**r zero *)
    end
  else if Z.eqb e (2 ^ ew - 1) then
    match m with
    | Zpos p => mk_nan s p                          (**r NaN with payload *)
    | _ => B754_infinity prec emax s                (**r infinity *)
    end
  else
    match m + 2 ^ mw with
    | Zpos p => mk_finite s p (e + emin - 1)        (**r normal *)
    | _ => B754_zero prec emax s                    (**r impossible *)
    end.

(** On valid arguments, [mk_finite] is the constructor. *)
Lemma mk_finite_eq:
  forall s m e (H : SpecFloat.bounded prec emax m e = true),
  mk_finite s m e = B754_finite prec emax s m e H.
Proof.
  intros s m e H. unfold mk_finite.
  generalize (@eq_refl bool (SpecFloat.bounded prec emax m e)).
  generalize (SpecFloat.bounded prec emax m e) at 2 3.
  intros b E; destruct b.
  - f_equal; apply bool_eq_proof_irrel.
  - congruence.
Qed.

(** On a valid payload, [mk_nan] is the constructor. *)
Lemma mk_nan_eq:
  forall s pl (H : nan_pl prec pl = true),
  mk_nan s pl = B754_nan prec emax s pl H.
Proof.
  intros s pl H. unfold mk_nan.
  generalize (@eq_refl bool (nan_pl prec pl)).
  generalize (nan_pl prec pl) at 2 3.
  intros b E; destruct b.
  - f_equal; apply bool_eq_proof_irrel.
  - congruence.
Qed.

Hypothesis Hmw : 0 < mw.
Hypothesis Hew : 1 < ew.
Hypothesis Hmax : prec < emax.

(** [2^ew] is twice [emax]. *)
Lemma emax_double: 2 ^ ew = 2 * emax.
Proof.
  replace ew with ((ew - 1) + 1) at 1 by ring.
  rewrite Z.pow_add_r by lia. lia.
Qed.

(** The subnormal case: a fraction below [2^mw] at exponent [emin]. *)
Lemma bounded_subnormal:
  forall p, Zpos p < 2 ^ mw -> SpecFloat.bounded prec emax p emin = true.
Proof.
  intros p Hp. unfold SpecFloat.bounded, SpecFloat.canonical_mantissa, SpecFloat.fexp.
  generalize (digits2_pos_le p mw ltac:(lia) Hp); intros D.
  apply andb_true_intro; split.
  - apply Zeq_bool_true. unfold SpecFloat.emin in *. lia.
  - apply Zle_bool_true. unfold SpecFloat.emin. lia.
Qed.

(** The normal case: [2^mw + m] with a biased exponent in [[1, 2^ew - 2]]. *)
Lemma bounded_normal:
  forall p e, 2 ^ mw <= Zpos p < 2 ^ (mw + 1) -> 1 <= e <= 2 ^ ew - 2 ->
  SpecFloat.bounded prec emax p (e + emin - 1) = true.
Proof.
  intros p e Hp He. unfold SpecFloat.bounded, SpecFloat.canonical_mantissa, SpecFloat.fexp.
  generalize (digits2_pos_le p (mw + 1) ltac:(lia) (proj2 Hp)); intros D1.
  generalize (digits2_pos_gt p mw ltac:(lia) (proj1 Hp)); intros D2.
  rewrite emax_double in He.
  apply andb_true_intro; split.
  - apply Zeq_bool_true. unfold SpecFloat.emin in *. lia.
  - apply Zle_bool_true. unfold SpecFloat.emin. lia.
Qed.

(** Every fraction field is a valid NaN payload. *)
Lemma nan_pl_small: forall p, Zpos p < 2 ^ mw -> nan_pl prec p = true.
Proof.
  intros p Hp. unfold nan_pl. apply Zlt_bool_true.
  generalize (digits2_pos_le p mw ltac:(lia) Hp). lia.
Qed.

(** The fields of a bit pattern are in range. *)
Lemma split_bits_range:
  forall x s m e, split_bits mw ew x = (s, m, e) ->
  0 <= m < 2 ^ mw /\ 0 <= e < 2 ^ ew.
Proof.
  unfold split_bits; intros x s m e H. inversion H; clear H; subst.
  split; apply Z.mod_pos_bound; apply Z.pow_pos_nonneg; lia.
Qed.

(** Every bit pattern in range is the encoding of its decoding. *)
Lemma bits_of_float_of_bits:
  forall x, 0 <= x < 2 ^ (mw + ew + 1) ->
  bits_of_binary_float mw ew (float_of_bits x) = x.
Proof.
  intros x Hx. generalize (join_split_bits mw ew Hmw ltac:(lia) x Hx).
  unfold float_of_bits.
  destruct (split_bits mw ew x) as [[s m] e] eqn:SPLIT.
  destruct (split_bits_range x s m e SPLIT) as [Hm He].
  intros J.
  destruct (Z.eqb_spec e 0) as [E0|E0].
  - (* zero or subnormal *)
    subst e. destruct m as [|p|p]; try lia.
    + exact J.
    + rewrite (mk_finite_eq s p emin (bounded_subnormal p (proj2 Hm))).
      unfold bits_of_binary_float; cbv beta iota zeta.
      rewrite Zle_bool_false by lia. exact J.
  - destruct (Z.eqb_spec e (2 ^ ew - 1)) as [E1|E1].
    + (* infinity or NaN *)
      subst e. destruct m as [|p|p]; try lia.
      * exact J.
      * rewrite (mk_nan_eq s p (nan_pl_small p (proj2 Hm))). exact J.
    + (* normal *)
      assert (Hp: 2 ^ mw <= m + 2 ^ mw < 2 ^ (mw + 1)).
      { rewrite Z.pow_add_r by lia. lia. }
      destruct (m + 2 ^ mw) as [|p|p] eqn:M; try lia.
      rewrite (mk_finite_eq s p (e + emin - 1) (bounded_normal p e Hp ltac:(lia))).
      unfold bits_of_binary_float; cbv beta iota zeta. rewrite <- M.
      rewrite Zle_bool_true by lia.
      replace (m + 2 ^ mw - 2 ^ mw) with m by ring.
      replace (e + emin - 1 - emin + 1) with e by ring.
      exact J.
Qed.

(** Every float is the decoding of its encoding. *)
Lemma float_of_bits_of_float:
  forall f, float_of_bits (bits_of_binary_float mw ew f) = f.
Proof.
  intros f. unfold float_of_bits.
  rewrite (split_bits_of_binary_float_correct mw ew Hmw ltac:(lia) f).
  assert (Hemax: 2 ^ ew - 1 <> 0).
  { assert (2 ^ 1 < 2 ^ ew) by (apply Z.pow_lt_mono_r; lia). lia. }
  destruct f as [s|s|s pl H|s m e H]; unfold split_bits_of_binary_float.
  - reflexivity.
  - cbv beta iota zeta.
    rewrite (proj2 (Z.eqb_neq _ _) Hemax), Z.eqb_refl. reflexivity.
  - cbv beta iota zeta.
    rewrite (proj2 (Z.eqb_neq _ _) Hemax), Z.eqb_refl.
    apply mk_nan_eq.
  - assert (B := H).
    unfold SpecFloat.bounded, SpecFloat.canonical_mantissa, SpecFloat.fexp in B.
    apply andb_prop in B; destruct B as [B1 B2].
    apply Zeq_bool_eq in B1. apply Zle_bool_imp_le in B2.
    generalize emax_double; intros ED.
    destruct (Zle_bool_spec 0 (Zpos m - 2 ^ mw)) as [Hm|Hm];
      cbv beta iota zeta.
    + (* normal *)
      rewrite (proj2 (Z.eqb_neq _ _)) by (unfold SpecFloat.emin in *; lia).
      rewrite (proj2 (Z.eqb_neq _ _)) by (unfold SpecFloat.emin in *; lia).
      replace (Zpos m - 2 ^ mw + 2 ^ mw) with (Zpos m) by ring.
      replace (e - emin + 1 + emin - 1) with e by ring.
      apply mk_finite_eq.
    + (* subnormal: the exponent is necessarily [emin] *)
      rewrite Z.eqb_refl.
      generalize (digits2_pos_le m mw ltac:(lia) ltac:(lia)); intros D.
      assert (e = emin) by (unfold SpecFloat.emin in *; lia).
      subst e. apply mk_finite_eq.
Qed.

End OF_BITS.

(** ** Binary64 and binary32 *)

(** [double] from its 64-bit pattern. *)
Definition float64_of_bits (z : Z) : float64 := float_of_bits 52 11 z.

(** [float] from its 32-bit pattern. *)
Definition float32_of_bits (z : Z) : float32 := float_of_bits 23 8 z.

(** Main results, for [double] and [float]. *)
Theorem bits_of_float64_of_bits:
  forall z, 0 <= z < 2 ^ 64 -> bits_of_b64 (float64_of_bits z) = z.
Proof.
  intros z Hz. apply (bits_of_float_of_bits 52 11); try reflexivity; exact Hz.
Qed.

Theorem float64_of_bits_of_float64:
  forall f : float64, float64_of_bits (bits_of_b64 f) = f.
Proof.
  intros f. apply (float_of_bits_of_float 52 11); reflexivity.
Qed.

Theorem bits_of_float32_of_bits:
  forall z, 0 <= z < 2 ^ 32 -> bits_of_b32 (float32_of_bits z) = z.
Proof.
  intros z Hz. apply (bits_of_float_of_bits 23 8); try reflexivity; exact Hz.
Qed.

Theorem float32_of_bits_of_float32:
  forall f : float32, float32_of_bits (bits_of_b32 f) = f.
Proof.
  intros f. apply (float_of_bits_of_float 23 8); reflexivity.
Qed.

(** Bit patterns are in range. *)
Lemma bits_of_b64_range: forall f, 0 <= bits_of_b64 f < 2 ^ 64.
Proof.
  intros f. apply (bits_of_binary_float_range 52 11); reflexivity.
Qed.

Lemma bits_of_b32_range: forall f, 0 <= bits_of_b32 f < 2 ^ 32.
Proof.
  intros f. apply (bits_of_binary_float_range 23 8); reflexivity.
Qed.
