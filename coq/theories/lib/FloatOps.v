(** * IEEE 754 arithmetic without axioms *)

(** Multiplication, addition, subtraction and division of binary64
    ([double]) and binary32 ([float]) numbers, rounded to nearest, ties to
    even (the C default), on Flocq's [binary_float] (the library's
    [float64] and [float32]), with no axiom anywhere.

    Policy of the library: no theorem may depend on an axiom ([make -C coq
    check-assumptions]).  Flocq's own operations ([Bmult], [Bplus],
    [Bminus], [Bdiv]) build the validity proof of their result with
    real-number lemmas, so whatever computes with them depends on the
    classical axioms of Coq's reals.  Float arithmetic therefore goes
    through this file, never through Flocq's real-number-based operations
    in definitions that theorems mention.

    How: a float is turned into Coq's own [SpecFloat.spec_float] by
    Flocq's [B2SF] (a plain match), the operation is computed by Coq's
    [SpecFloat] ([SFmul], [SFadd], [SFsub], [SFdiv]: the specification of
    Coq's primitive floats, integer arithmetic only), and the result is
    turned back into a [binary_float] by [of_spec], which obtains the
    validity proof of a finite result by computing the boolean check and
    matching on it ([FloatBits.mk_finite]), as [FloatBits] decodes bit
    patterns.  (The [false] branch of that check is unreachable: Flocq
    proves it, with the reals, in [Bmult_correct] and its siblings; here it
    yields a zero and is never taken by the examples below.)

    NaNs: [spec_float] has a single NaN, so the NaN of a result is chosen
    here ([nan_of]), as x86-64 (SSE2) does: the first operand that is a
    NaN, made quiet (the top bit of its payload set), otherwise the
    default NaN (negative, quiet, payload [2^(mw-1)]: [0xFFF8000000000000]
    for [double]).  C leaves NaN payloads unspecified, and a compiler may
    swap the operands of [*] and [+], so a comparison with compiled C
    should only require a NaN where this gives a NaN.

    Main results (closed under the global context, restated in [Main]):
    [mul64_comm], [add64_comm], [mul32_comm], [add32_comm] (commutativity
    when at most one operand is a NaN), and worked examples checked by
    [vm_compute] against the bit patterns that gcc computes: [0.1 * 3],
    [0.1 + 0.2], [0.1f * 3.0f], a subnormal rounded to even, [inf * 0]
    and the propagation of a NaN payload. *)

From Coq Require Import ZArith Bool.
From Coq Require Import Floats.SpecFloat.
From Flocq Require Import IEEE754.Binary IEEE754.Bits.
From ROSGen Require Import FloatBits.

Local Open Scope Z_scope.

(** The two formats ([ROSGen.Syntax.float64], [ROSGen.Syntax.float32]). *)
Local Notation float64 := (binary_float 53 1024).
Local Notation float32 := (binary_float 24 128).

(** ** The generic operations *)

Section OPS.

(** [mw] bits of fraction, [ew] bits of exponent (as in [FloatBits]). *)
Variables mw ew : Z.

Local Notation prec := (mw + 1).
Local Notation emax := (2 ^ (ew - 1)).
Local Notation float := (binary_float prec emax).

(** A result of [SpecFloat] as a float; [nan] stands for its NaN. *)
Definition of_spec (nan : float) (r : spec_float) : float :=
  match r with
  | S754_zero s => B754_zero prec emax s
  | S754_infinity s => B754_infinity prec emax s
  | S754_nan => nan
  | S754_finite s m e => mk_finite mw ew s m e
  end.

(** The quiet bit of a NaN payload: the most significant fraction bit. *)
Definition quiet_bit : positive := Pos.shiftl 1 (Z.to_N (mw - 1)).

(** The default NaN: negative, quiet, no other payload bit. *)
Definition default_nan : float := mk_nan mw ew true quiet_bit.

(** The NaN of an operation on [x] and [y] that gives a NaN: the first
    NaN operand, made quiet; otherwise the default NaN. *)
Definition nan_of (x y : float) : float :=
  match x, y with
  | B754_nan _ _ s pl _, _ => mk_nan mw ew s (Pos.lor pl quiet_bit)
  | _, B754_nan _ _ s pl _ => mk_nan mw ew s (Pos.lor pl quiet_bit)
  | _, _ => default_nan
  end.

(** A binary operation of [SpecFloat] on floats. *)
Definition binop (op : spec_float -> spec_float -> spec_float) (x y : float) : float :=
  of_spec (nan_of x y) (op (B2SF prec emax x) (B2SF prec emax y)).

Definition fmul : float -> float -> float := binop (SFmul prec emax).
Definition fadd : float -> float -> float := binop (SFadd prec emax).
Definition fsub : float -> float -> float := binop (SFsub prec emax).
Definition fdiv : float -> float -> float := binop (SFdiv prec emax).

(** ** Commutativity *)

(** [SpecFloat]'s multiplication and addition are commutative. *)
Lemma SFmul_comm: forall x y, SFmul prec emax x y = SFmul prec emax y x.
Proof.
  intros x y; unfold SFmul.
  destruct x as [sx|sx| |sx mx ex], y as [sy|sy| |sy my ey]; cbv beta iota;
    try reflexivity; try (f_equal; apply xorb_comm).
  rewrite (xorb_comm sx sy), (Pos.mul_comm mx my), (Z.add_comm ex ey). reflexivity.
Qed.

Lemma SFadd_comm: forall x y, SFadd prec emax x y = SFadd prec emax y x.
Proof.
  intros x y; unfold SFadd.
  destruct x as [sx|sx| |sx mx ex], y as [sy|sy| |sy my ey]; cbv beta iota zeta;
    try reflexivity; try (destruct sx, sy; reflexivity).
  rewrite (Z.min_comm ey ex). f_equal. apply Z.add_comm.
Qed.

(** The NaN chosen does not depend on the order of the operands when at
    most one of them is a NaN. *)
Lemma nan_of_comm:
  forall x y, is_nan prec emax x = false \/ is_nan prec emax y = false ->
  nan_of x y = nan_of y x.
Proof.
  intros [sx|sx|sx plx Hx|sx mx ex Hx] [sy|sy|sy ply Hy|sy my ey Hy] H; simpl in H;
    try reflexivity; destruct H; discriminate.
Qed.

Lemma fmul_comm:
  forall x y, is_nan prec emax x = false \/ is_nan prec emax y = false -> fmul x y = fmul y x.
Proof.
  intros x y H. unfold fmul, binop. rewrite nan_of_comm, SFmul_comm by exact H. reflexivity.
Qed.

Lemma fadd_comm:
  forall x y, is_nan prec emax x = false \/ is_nan prec emax y = false -> fadd x y = fadd y x.
Proof.
  intros x y H. unfold fadd, binop. rewrite nan_of_comm, SFadd_comm by exact H. reflexivity.
Qed.

End OPS.

(** ** Binary64 and binary32 *)

Definition mul64 : float64 -> float64 -> float64 := fmul 52 11.
Definition add64 : float64 -> float64 -> float64 := fadd 52 11.
Definition sub64 : float64 -> float64 -> float64 := fsub 52 11.
Definition div64 : float64 -> float64 -> float64 := fdiv 52 11.

Definition mul32 : float32 -> float32 -> float32 := fmul 23 8.
Definition add32 : float32 -> float32 -> float32 := fadd 23 8.
Definition sub32 : float32 -> float32 -> float32 := fsub 23 8.
Definition div32 : float32 -> float32 -> float32 := fdiv 23 8.

(** Multiplication and addition commute, unless both operands are NaNs
    (then the result is the first one, quieted). *)
Theorem mul64_comm:
  forall x y : float64, is_nan 53 1024 x = false \/ is_nan 53 1024 y = false ->
  mul64 x y = mul64 y x.
Proof. exact (fmul_comm 52 11). Qed.

Theorem add64_comm:
  forall x y : float64, is_nan 53 1024 x = false \/ is_nan 53 1024 y = false ->
  add64 x y = add64 y x.
Proof. exact (fadd_comm 52 11). Qed.

Theorem mul32_comm:
  forall x y : float32, is_nan 24 128 x = false \/ is_nan 24 128 y = false ->
  mul32 x y = mul32 y x.
Proof. exact (fmul_comm 23 8). Qed.

Theorem add32_comm:
  forall x y : float32, is_nan 24 128 x = false \/ is_nan 24 128 y = false ->
  add32 x y = add32 y x.
Proof. exact (fadd_comm 23 8). Qed.

(** ** Worked examples, on bit patterns *)

(** The operation [op] on the floats of the patterns [a] and [b], as a
    pattern. *)
Definition on_bits64 (op : float64 -> float64 -> float64) (a b : Z) : Z :=
  bits_of_b64 (op (float64_of_bits a) (float64_of_bits b)).
Definition on_bits32 (op : float32 -> float32 -> float32) (a b : Z) : Z :=
  bits_of_b32 (op (float32_of_bits a) (float32_of_bits b)).

(** [0.1 * 3 = 0.30000000000000004] and [0.1 + 0.2] is the same double
    (the patterns gcc computes). *)
Theorem mul64_example: on_bits64 mul64 0x3FB999999999999A 0x4008000000000000 = 0x3FD3333333333334.
Proof. vm_compute. reflexivity. Qed.

Theorem add64_example: on_bits64 add64 0x3FB999999999999A 0x3FC999999999999A = 0x3FD3333333333334.
Proof. vm_compute. reflexivity. Qed.

(** [0.1f * 3.0f]. *)
Theorem mul32_example: on_bits32 mul32 0x3DCCCCCD 0x40400000 = 0x3E99999A.
Proof. vm_compute. reflexivity. Qed.

(** Ties go to even: 1.5 times the least subnormal is 2 times it, and
    [1 / 3] is rounded to nearest. *)
Theorem mul64_tie_even: on_bits64 mul64 0x1 0x3FF8000000000000 = 0x2.
Proof. vm_compute. reflexivity. Qed.

Theorem div64_example: on_bits64 div64 0x3FF0000000000000 0x4008000000000000 = 0x3FD5555555555555.
Proof. vm_compute. reflexivity. Qed.

(** Overflow gives infinity, [inf * 0] the default NaN, and a NaN
    operand is propagated, quieted (a signalling NaN with payload 1
    becomes the quiet NaN with payload [2^51 + 1]). *)
Theorem mul64_overflow: on_bits64 mul64 0x7FE1CCF385EBC8A0 0x4024000000000000 = 0x7FF0000000000000.
Proof. vm_compute. reflexivity. Qed.

Theorem mul64_inf_zero: on_bits64 mul64 0x7FF0000000000000 0x0 = 0xFFF8000000000000.
Proof. vm_compute. reflexivity. Qed.

Theorem mul64_nan_payload: on_bits64 mul64 0x7FF0000000000001 0x3FF0000000000000 = 0x7FF8000000000001.
Proof. vm_compute. reflexivity. Qed.
