(** * Examples for the C printer *)

(** One program, [the_program], that exercises every construct the
    printer handles: struct copy through a pointer argument, nested field
    reads and writes, arrays, [while] and [for (;;)] loops with [break],
    [if] with and without [else], calls with and without a result
    (internal and external), casts, integer constants at the extremes of
    every type and wrapping around, float constants ([-0.0], subnormals,
    [0.1], the largest double, non-finite values), [float] constants, and
    an [extern] global.

    [tests/coq/test_printer.py] prints it through the extraction path
    ([coq/extraction/print_program.sh]), compiles the C text with
    [gcc -std=c11 -Wall -Wextra -Werror -pedantic], runs it with a small
    harness that calls [run_all] and prints every global, and compares the
    output with [interp_dump] below: the same globals after the same run,
    computed by the Coq interpreter ([Interp.run_program]).

    The [Example]s at the end check a few printed forms by computation. *)

From Coq Require Import String List ZArith.
From Flocq Require Import IEEE754.Binary IEEE754.Bits.
From ROSGen Require Import Syntax FloatBits Printer Dump Values Memory Environment Semantics Typing Interp.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope Z_scope.

(** ** The program *)

Definition tV := Tstruct "Vec3".
Definition tM := Tstruct "Msg".
Definition tschar := Tint I8 Signed.
Definition tshort := Tint I16 Signed.
Definition tushort := Tint I16 Unsigned.
Definition tlong := Tlong Signed.
Definition tulong := Tlong Unsigned.

Definition comp_V := Composite "Vec3" [("x", tdouble); ("y", tdouble); ("z", tdouble)].
Definition comp_M := Composite "Msg"
  [("lin", tV); ("cov", Tarray tdouble 4); ("s8", tschar); ("u8", tuchar);
   ("s16", tshort); ("u16", tushort); ("s32", tint); ("u32", tuint);
   ("s64", tlong); ("u64", tulong); ("f32", tfloat)].

Definition fn (ret : type) (params vars temps : list (ident * type)) (body : statement) : globdef :=
  Gfun (Internal (mkfunction ret params vars temps body)).

Fixpoint seq (l : list statement) : statement :=
  match l with
  | [] => Sskip
  | [s] => s
  | s :: l' => Ssequence s (seq l')
  end.

Definition gv (x : ident) (ty : type) : expr := Evar x ty.
Definition tv (x : ident) (ty : type) : expr := Etempvar x ty.
Definition fld (e : expr) (f : ident) (ty : type) : expr := Efield e f ty.
Definition ci (n : Z) (ty : type) : expr := Econst_int n ty.
Definition cl (n : Z) (ty : type) : expr := Econst_long n ty.
Definition cd (bits : Z) : expr := Econst_float (float64_of_bits bits) tdouble.
Definition cf (bits : Z) : expr := Econst_single (float32_of_bits bits) tfloat.
Definition fnty (args : list type) (res : type) : type := Tfunction args res.
Definition call0 (f : ident) : statement := Scall None (Evar f (fnty [] Tvoid)) [].

Definition gd := gv "g_d" (Tarray tdouble 8).
Definition gf := gv "g_f" (Tarray tfloat 4).
Definition msg := tv "msg" (tptr tM).

(** [void ints(void)]: integer constants, wrapped to their types. *)
Definition f_ints : globdef := fn Tvoid [] [] [("t", tlong); ("u", tint)] (seq [
  Sassign (gv "g_i32" tint) (ci (-2147483648) tint);           (* INT_MIN *)
  Sassign (gv "g_u32" tuint) (ci (-1) tuint);                   (* 4294967295U *)
  Sassign (gv "g_i64" tlong) (cl (-9223372036854775808) tlong); (* LLONG_MIN *)
  Sassign (gv "g_u64" tulong) (cl (-1) tulong);                 (* ULLONG_MAX *)
  Sassign (gv "g_i8" tschar) (ci 128 tschar);                   (* wraps to -128 *)
  Sassign (gv "g_u8" tuchar) (ci 300 tuchar);                   (* wraps to 44 *)
  Sassign (gv "g_i16" tshort) (ci 40000 tshort);                (* wraps to -25536 *)
  Sassign (gv "g_u16" tushort) (ci (-1) tushort);               (* 65535 *)
  Sassign (gv "g_i32b" tint) (ci 2147483648 tint);              (* wraps to INT_MIN *)
  Sassign (gv "g_i64b" tlong) (cl 9223372036854775807 tlong);   (* LLONG_MAX *)
  (* casts *)
  Sassign (gv "g_c1" tschar) (Ecast (ci 200 tint) tschar);      (* -56 *)
  Sset "t" (cl 5000000007 tlong);
  Sassign (gv "g_c2" tint) (Ecast (tv "t" tlong) tint);         (* 705032711 *)
  Sassign (gv "g_c3" tuchar) (Ecast (tv "t" tlong) tuchar);     (* 7 *)
  Sset "u" (ci (-3) tint);
  Sassign (gv "g_c4" tulong) (Ecast (tv "u" tint) tulong);      (* 2^64 - 3 *)
  Sassign (gv "g_c5" tushort) (Ecast (Ecast (tv "u" tint) tschar) tushort); (* 65533 *)
  Sreturn None]).

(** [void floats(void)]: exact float constants. *)
Definition f_floats : globdef := fn Tvoid [] [] [("i", tint)] (seq [
  Sassign (Eindex gd (ci 0 tint) tdouble) (cd 0x8000000000000000);  (* -0.0 *)
  Sassign (Eindex gd (ci 1 tint) tdouble) (cd 0x0000000000000001);  (* min subnormal *)
  Sassign (Eindex gd (ci 2 tint) tdouble) (cd 0x3FB999999999999A);  (* 0.1 *)
  Sassign (Eindex gd (ci 3 tint) tdouble) (cd 0x7FEFFFFFFFFFFFFF);  (* DBL_MAX *)
  Sset "i" (ci 4 tint);
  Sassign (Eindex gd (tv "i" tint) tdouble) (cd 0xC008000000000000); (* -3.0 *)
  Sassign (Eindex gd (ci 5 tint) tdouble) (cd 0x000FFFFFFFFFFFFF);  (* max subnormal *)
  Sassign (Eindex gd (ci 6 tint) tdouble) (cd 0x7FF0000000000000);  (* +inf *)
  Sassign (Eindex gd (ci 7 tint) tdouble) (cd 0x7FF8000000000123);  (* NaN, payload *)
  Sassign (Eindex gf (ci 0 tint) tfloat) (cf 0x3DCCCCCD);           (* 0.1f *)
  Sassign (Eindex gf (ci 1 tint) tfloat) (cf 0x00000001);           (* min subnormal *)
  Sassign (Eindex gf (ci 2 tint) tfloat) (cf 0x80000000);           (* -0.0f *)
  Sassign (Eindex gf (ci 3 tint) tfloat) (cf 0xFF800000);           (* -inf *)
  Sreturn None]).

(** [void copy_msg(struct Msg *msg)]: nested fields through a pointer,
    struct copy from a pointer, writes through the pointer. *)
Definition f_copy : globdef :=
  fn Tvoid [("msg", tptr tM)] [] [("t", tdouble); ("p", tptr tV)] (seq [
  Sset "t" (fld (fld (Ederef msg tM) "lin" tV) "x" tdouble);
  Sassign (fld (fld (gv "g_out" tM) "lin" tV) "z" tdouble) (tv "t" tdouble);
  Sassign (gv "g_in" tM) (Ederef msg tM);
  Sset "p" (Eaddrof (fld (Ederef msg tM) "lin" tV) (tptr tV));
  Sassign (fld (Ederef (tv "p" (tptr tV)) tV) "y" tdouble) (tv "t" tdouble);
  Sassign (Eindex (fld (Ederef msg tM) "cov" (Tarray tdouble 4)) (ci 3 tint) tdouble)
          (tv "t" tdouble);
  Sassign (gv "g_out2" tM) (Ederef msg tM);
  Sreturn None]).

(** [double get_x(struct Vec3 *v)] and [int ret_neg(void)]: calls that
    return a value. *)
Definition f_get_x : globdef :=
  fn tdouble [("v", tptr tV)] [] []
     (Sreturn (Some (fld (Ederef (tv "v" (tptr tV)) tV) "x" tdouble))).
Definition f_ret_neg : globdef := fn tint [] [] [] (Sreturn (Some (ci (-7) tint))).

(** [void loops(void)]: [while] with a condition, [for (;;)] with a
    [break] in the middle, [if] with both branches. *)
Definition f_loops : globdef := fn Tvoid [] [] [("k", tint)] (seq [
  Sassign (gv "g_flag" tint) (ci 1 tint);
  Swhile (gv "g_flag" tint) (seq [
    Sassign (gv "g_flag" tint) (ci 0 tint);
    Sassign (gv "g_count" tint) (ci 11 tint)]);
  Sloop (seq [
    Sassign (gv "g_count2" tint) (ci 22 tint);
    Sifthenelse (gv "g_count2" tint) Sbreak Sskip;
    Sassign (gv "g_count2" tint) (ci 99 tint)]);
  Sset "k" (ci 0 tint);
  Sifthenelse (tv "k" tint)
    (Sassign (gv "g_branch" tint) (ci 1 tint))
    (Sassign (gv "g_branch" tint) (ci 2 tint));
  Sifthenelse (Eindex gd (ci 0 tint) tdouble)        (* -0.0 is false *)
    (Sassign (gv "g_branch2" tint) (ci 1 tint))
    Sskip;
  Sifthenelse (Eindex gd (ci 7 tint) tdouble)        (* NaN is true *)
    (Sassign (gv "g_branch3" tint) (ci 1 tint))
    Sskip;
  Sreturn None]).

(** [void arith(void)]: the operators on each type they allow, from
    temporaries (not constants), with results at the edges: wrap-around
    of unsigned arithmetic, truncating division, remainders of negative
    numbers, [-0.0], rounding to nearest even, overflow to infinity, a
    NaN operand propagated, NaN comparisons. *)
Definition bop (op : binary_operation) (a b : expr) (ty : type) : expr := Ebinop op a b ty.
Definition uop (op : unary_operation) (a : expr) (ty : type) : expr := Eunop op a ty.
Definition ai (i : Z) := Eindex (gv "g_ai" (Tarray tint 16)) (ci i tint) tint.
Definition au (i : Z) := Eindex (gv "g_au" (Tarray tuint 6)) (ci i tint) tuint.
Definition al (i : Z) := Eindex (gv "g_al" (Tarray tlong 6)) (ci i tint) tlong.
Definition aul (i : Z) := Eindex (gv "g_aul" (Tarray tulong 4)) (ci i tint) tulong.
Definition ad (i : Z) := Eindex (gv "g_ad" (Tarray tdouble 12)) (ci i tint) tdouble.
Definition af (i : Z) := Eindex (gv "g_af" (Tarray tfloat 5)) (ci i tint) tfloat.
Definition ac (i : Z) := Eindex (gv "g_ac" (Tarray tint 16)) (ci i tint) tint.

Definition f_arith : globdef :=
  fn Tvoid [] [] [("a", tint); ("b", tint); ("c", tint); ("ua", tuint); ("ub", tuint);
                  ("la", tlong); ("lb", tlong); ("ula", tulong); ("ulb", tulong);
                  ("x", tdouble); ("y", tdouble); ("z", tdouble); ("n", tdouble);
                  ("f", tfloat); ("g", tfloat)] (seq [
  Sset "a" (ci (-7) tint); Sset "b" (ci 2 tint); Sset "c" (ci 2147483647 tint);
  Sassign (ai 0) (bop Oadd (tv "a" tint) (tv "b" tint) tint);            (* -5 *)
  Sassign (ai 1) (bop Odiv (tv "a" tint) (tv "b" tint) tint);            (* -3 *)
  Sassign (ai 2) (bop Omod (tv "a" tint) (tv "b" tint) tint);            (* -1 *)
  Sassign (ai 3) (bop Osub (tv "c" tint) (tv "b" tint) tint);            (* INT_MAX - 2 *)
  Sassign (ai 4) (bop Omul (tv "a" tint) (ci (-6) tint) tint);           (* 42 *)
  Sassign (ai 5) (bop Oand (tv "a" tint) (ci 12 tint) tint);             (* 8 *)
  Sassign (ai 6) (bop Oor (tv "a" tint) (ci 12 tint) tint);              (* -3 *)
  Sassign (ai 7) (bop Oxor (tv "a" tint) (ci 12 tint) tint);             (* -11 *)
  Sassign (ai 8) (uop Oneg (tv "a" tint) tint);                          (* 7 *)
  Sassign (ai 9) (uop Oneg (ci (-3) tint) tint);                         (* (-(-3)) = 3 *)
  Sassign (ai 10) (uop Onotbool (tv "b" tint) tint);                     (* 0 *)
  Sassign (ai 11) (bop Osub (bop Omul (tv "b" tint) (tv "b" tint) tint)
                            (bop Odiv (tv "c" tint) (ci 1000 tint) tint) tint); (* 4 - 2147483 *)
  Sassign (ai 12) (bop Omod (ci 7 tint) (uop Oneg (tv "b" tint) tint) tint);   (* 1 *)
  Sassign (ai 13) (bop Odiv (tv "c" tint) (uop Oneg (tv "c" tint) tint) tint); (* -1 *)
  Sassign (ai 14) (bop Omod (bop Oadd (tv "a" tint) (ci 0 tint) tint) (ci 7 tint) tint); (* 0 *)
  Sassign (ai 15) (uop Onotbool (ci 0 tint) tint);                       (* 1 *)
  Sset "ua" (ci 0 tuint); Sset "ub" (ci 4000000000 tuint);
  Sassign (au 0) (bop Osub (tv "ua" tuint) (ci 1 tuint) tuint);          (* 4294967295 *)
  Sassign (au 1) (bop Oadd (tv "ub" tuint) (tv "ub" tuint) tuint);       (* 3705032704 *)
  Sassign (au 2) (bop Odiv (tv "ub" tuint) (ci 7 tuint) tuint);          (* 571428571 *)
  Sassign (au 3) (bop Omod (tv "ub" tuint) (ci 7 tuint) tuint);          (* 3 *)
  Sassign (au 4) (uop Oneg (tv "ub" tuint) tuint);                       (* 294967296 *)
  Sassign (au 5) (bop Omul (tv "ub" tuint) (tv "ub" tuint) tuint);       (* wraps *)
  Sset "la" (cl (-9) tlong); Sset "lb" (cl 9223372036854775807 tlong);
  Sassign (al 0) (bop Odiv (tv "la" tlong) (cl 4 tlong) tlong);          (* -2 *)
  Sassign (al 1) (bop Omod (tv "la" tlong) (cl 4 tlong) tlong);          (* -1 *)
  Sassign (al 2) (bop Osub (tv "lb" tlong) (cl 1 tlong) tlong);          (* LLONG_MAX - 1 *)
  Sassign (al 3) (bop Omul (tv "la" tlong) (cl 1000000000000 tlong) tlong);
  Sassign (al 4) (uop Oneg (tv "lb" tlong) tlong);                       (* -LLONG_MAX *)
  Sassign (al 5) (bop Oxor (tv "la" tlong) (tv "lb" tlong) tlong);       (* 8 *)
  Sset "ula" (cl (-1) tulong); Sset "ulb" (cl 2 tulong);
  Sassign (aul 0) (bop Oadd (tv "ula" tulong) (tv "ulb" tulong) tulong); (* 1 *)
  Sassign (aul 1) (bop Omul (tv "ula" tulong) (tv "ulb" tulong) tulong); (* 2^64 - 2 *)
  Sassign (aul 2) (bop Odiv (tv "ula" tulong) (tv "ulb" tulong) tulong); (* 2^63 - 1 *)
  Sassign (aul 3) (uop Oneg (tv "ulb" tulong) tulong);                   (* 2^64 - 2 *)
  Sset "x" (cd 0x3FB999999999999A); Sset "y" (cd 0x4008000000000000);    (* 0.1, 3.0 *)
  Sset "z" (cd 0x8000000000000000); Sset "n" (cd 0x7FF8000000000123);    (* -0.0, NaN *)
  Sassign (ad 0) (bop Omul (tv "x" tdouble) (tv "y" tdouble) tdouble);   (* 0.30000000000000004 *)
  Sassign (ad 1) (bop Oadd (tv "x" tdouble) (cd 0x3FC999999999999A) tdouble); (* 0.1 + 0.2 *)
  Sassign (ad 2) (bop Odiv (cd 0x3FF0000000000000) (tv "y" tdouble) tdouble); (* 1/3 *)
  Sassign (ad 3) (bop Osub (tv "x" tdouble) (tv "x" tdouble) tdouble);   (* +0.0 *)
  Sassign (ad 4) (uop Oneg (tv "z" tdouble) tdouble);                    (* +0.0 *)
  Sassign (ad 5) (uop Oabsfloat (uop Oneg (tv "y" tdouble) tdouble) tdouble); (* 3.0 *)
  Sassign (ad 6) (bop Omul (cd 0x7FE1CCF385EBC8A0) (cd 0x4024000000000000) tdouble); (* +inf *)
  Sassign (ad 7) (bop Oadd (tv "n" tdouble) (tv "y" tdouble) tdouble);   (* the NaN *)
  Sassign (ad 8) (uop Oneg (tv "n" tdouble) tdouble);                    (* sign flipped *)
  Sassign (ad 9) (uop Oabsfloat (uop Oneg (tv "n" tdouble) tdouble) tdouble); (* the NaN *)
  Sassign (ad 10) (bop Omul (cd 0x0000000000000001) (cd 0x3FF8000000000000) tdouble); (* tie to even *)
  Sassign (ad 11) (uop Oneg (cd 0xBFF0000000000000) tdouble);            (* (-(-0x1p+0)) *)
  Sset "f" (cf 0x3DCCCCCD); Sset "g" (cf 0x40400000);                    (* 0.1f, 3.0f *)
  Sassign (af 0) (bop Omul (tv "f" tfloat) (tv "g" tfloat) tfloat);
  Sassign (af 1) (bop Odiv (tv "f" tfloat) (tv "g" tfloat) tfloat);
  Sassign (af 2) (bop Osub (tv "f" tfloat) (tv "g" tfloat) tfloat);
  Sassign (af 3) (uop Oabsfloat (cf 0xFF800000) tfloat);                 (* +inf *)
  Sassign (af 4) (uop Oneg (tv "f" tfloat) tfloat);
  Sassign (ac 0) (bop Olt (tv "a" tint) (tv "b" tint) tint);             (* 1 *)
  Sassign (ac 1) (bop Oge (tv "a" tint) (tv "b" tint) tint);             (* 0 *)
  Sassign (ac 2) (bop Ogt (tv "ub" tuint) (tv "ua" tuint) tint);         (* 1 *)
  Sassign (ac 3) (bop Ole (tv "ula" tulong) (tv "ulb" tulong) tint);     (* 0 *)
  Sassign (ac 4) (bop Oeq (tv "la" tlong) (cl (-9) tlong) tint);         (* 1 *)
  Sassign (ac 5) (bop One (tv "la" tlong) (cl (-9) tlong) tint);         (* 0 *)
  Sassign (ac 6) (bop Oeq (tv "z" tdouble) (bop Osub (tv "x" tdouble) (tv "x" tdouble) tdouble) tint); (* -0 == +0 *)
  Sassign (ac 7) (bop Olt (tv "n" tdouble) (tv "y" tdouble) tint);       (* 0: unordered *)
  Sassign (ac 8) (bop Oge (tv "n" tdouble) (tv "y" tdouble) tint);       (* 0 *)
  Sassign (ac 9) (bop One (tv "n" tdouble) (tv "n" tdouble) tint);       (* 1 *)
  Sassign (ac 10) (bop Oeq (tv "n" tdouble) (tv "n" tdouble) tint);      (* 0 *)
  Sassign (ac 11) (uop Onotbool (tv "z" tdouble) tint);                  (* 1 *)
  Sassign (ac 12) (uop Onotbool (tv "n" tdouble) tint);                  (* 0 *)
  Sassign (ac 13) (bop Ogt (tv "g" tfloat) (tv "f" tfloat) tint);        (* 1 *)
  Sassign (ac 14) (bop Ole (cd 0x7FF0000000000000) (tv "y" tdouble) tint); (* 0 *)
  Sassign (ac 15) (uop Onotbool (tv "ula" tulong) tint);                 (* 0 *)
  Sreturn None]).

(** [int run_all(void)]: the entry point, called by the harness. *)
Definition f_run_all : globdef :=
  fn tint [] [("loc", tM)] [("d", tdouble); ("r", tint); ("ok", tint)] (seq [
  call0 "ints";
  call0 "floats";
  Sassign (fld (fld (gv "loc" tM) "lin" tV) "x" tdouble) (cd 0x3FF8000000000000); (* 1.5 *)
  Sassign (fld (fld (gv "loc" tM) "lin" tV) "y" tdouble) (cd 0x0000000000000000);
  Sassign (fld (fld (gv "loc" tM) "lin" tV) "z" tdouble) (cd 0x0000000000000000);
  Sassign (Eindex (fld (gv "loc" tM) "cov" (Tarray tdouble 4)) (ci 0 tint) tdouble) (cd 0x4000000000000000);
  Sassign (Eindex (fld (gv "loc" tM) "cov" (Tarray tdouble 4)) (ci 1 tint) tdouble) (cd 0x0000000000000000);
  Sassign (Eindex (fld (gv "loc" tM) "cov" (Tarray tdouble 4)) (ci 2 tint) tdouble) (cd 0x0000000000000000);
  Sassign (Eindex (fld (gv "loc" tM) "cov" (Tarray tdouble 4)) (ci 3 tint) tdouble) (cd 0x0000000000000000);
  Sassign (fld (gv "loc" tM) "s8" tschar) (ci (-128) tschar);
  Sassign (fld (gv "loc" tM) "u8" tuchar) (ci 255 tuchar);
  Sassign (fld (gv "loc" tM) "s16" tshort) (ci (-32768) tshort);
  Sassign (fld (gv "loc" tM) "u16" tushort) (ci 65535 tushort);
  Sassign (fld (gv "loc" tM) "s32" tint) (ci 2147483647 tint);
  Sassign (fld (gv "loc" tM) "u32" tuint) (ci 4294967295 tuint);
  Sassign (fld (gv "loc" tM) "s64" tlong) (cl (-9223372036854775808) tlong);
  Sassign (fld (gv "loc" tM) "u64" tulong) (cl 18446744073709551615 tulong);
  Sassign (fld (gv "loc" tM) "f32" tfloat) (cf 0x3F800000);
  Scall None (Evar "copy_msg" (fnty [tptr tM] Tvoid)) [Eaddrof (gv "loc" tM) (tptr tM)];
  Scall (Some "d") (Evar "get_x" (fnty [tptr tV] tdouble))
        [Eaddrof (fld (gv "g_in" tM) "lin" tV) (tptr tV)];
  Sassign (gv "g_x" tdouble) (tv "d" tdouble);
  Scall (Some "r") (Evar "ret_neg" (fnty [] tint)) [];
  Sassign (gv "g_r" tint) (tv "r" tint);
  call0 "loops";
  call0 "arith";
  Scall (Some "ok") (Evar "ros_ok" (fnty [] tint)) [];
  Sassign (gv "g_ok" tint) (tv "ok" tint);
  Scall None (Evar "ros_subscribe_t" (fnty [tptr (fnty [tptr tM] Tvoid)] Tvoid))
        [Eaddrof (Evar "copy_msg" (fnty [tptr tM] Tvoid)) (tptr (fnty [tptr tM] Tvoid))];
  Sassign (gv "g_ext" tint) (ci 5 tint);
  Sreturn (Some (ci 0 tint))]).

Definition the_program : program := {|
  prog_types := [comp_V; comp_M];
  prog_defs := [
    ("g_in", Gvar tM); ("g_out", Gvar tM); ("g_out2", Gvar tM);
    ("g_i32", Gvar tint); ("g_u32", Gvar tuint); ("g_i64", Gvar tlong);
    ("g_u64", Gvar tulong); ("g_i8", Gvar tschar); ("g_u8", Gvar tuchar);
    ("g_i16", Gvar tshort); ("g_u16", Gvar tushort); ("g_i32b", Gvar tint);
    ("g_i64b", Gvar tlong); ("g_c1", Gvar tschar); ("g_c2", Gvar tint);
    ("g_c3", Gvar tuchar); ("g_c4", Gvar tulong); ("g_c5", Gvar tushort);
    ("g_d", Gvar (Tarray tdouble 8)); ("g_f", Gvar (Tarray tfloat 4));
    ("g_x", Gvar tdouble); ("g_r", Gvar tint); ("g_flag", Gvar tint);
    ("g_count", Gvar tint); ("g_count2", Gvar tint); ("g_branch", Gvar tint);
    ("g_branch2", Gvar tint); ("g_branch3", Gvar tint); ("g_ok", Gvar tint);
    ("g_ext", Gvar tint);
    ("g_ai", Gvar (Tarray tint 16)); ("g_au", Gvar (Tarray tuint 6));
    ("g_al", Gvar (Tarray tlong 6)); ("g_aul", Gvar (Tarray tulong 4));
    ("g_ad", Gvar (Tarray tdouble 12)); ("g_af", Gvar (Tarray tfloat 5));
    ("g_ac", Gvar (Tarray tint 16));
    ("ros_ok", Gfun (External EF_ros_ok [] tint));
    ("ros_subscribe_t", Gfun (External (EF_ros_subscribe "/t" "Msg" 1)
                                       [tptr (fnty [tptr tM] Tvoid)] Tvoid));
    ("ints", f_ints); ("floats", f_floats); ("copy_msg", f_copy);
    ("get_x", f_get_x); ("ret_neg", f_ret_neg); ("loops", f_loops);
    ("arith", f_arith);
    ("run_all", f_run_all)];
  prog_main := "run_all" |}.

(** [g_ext] is defined by the harness: the printer declares it [extern]. *)
Definition the_externs : list ident := ["g_ext"].

(** The program is well typed. *)
Example the_program_typechecks: check_program the_program = true.
Proof. vm_compute. reflexivity. Qed.

(** ** The interpreter's view: every global after [run_all] *)

(** One line per scalar leaf of a global: [path = value], integers in
    decimal, floats as their bit pattern ([0x] and 16 or 8 hex digits).
    The harness of the test prints the same format from the C run. *)
Definition render_val (v : val) : string :=
  match v with
  | Vint n | Vlong n => string_of_Z n
  | Vfloat f => "0x" ++ hex_digits 16 (bits_of_b64 f)
  | Vsingle f => "0x" ++ hex_digits 8 (bits_of_b32 f)
  | Vundef => "undef"
  | Vptr _ _ | Vfptr _ => "ptr"
  end.

Fixpoint render_mval (path : string) (mv : mval) : list string :=
  match mv with
  | MVscalar v => [path ++ " = " ++ render_val v]
  | MVstruct fs =>
      (fix go (l : list (ident * mval)) : list string :=
         match l with
         | [] => []
         | (f, m) :: l' => app (render_mval (path ++ "." ++ f) m) (go l')
         end) fs
  | MVarray es =>
      (fix go (i : Z) (l : list mval) : list string :=
         match l with
         | [] => []
         | m :: l' => app (render_mval (path ++ "[" ++ string_of_Z i ++ "]") m) (go (i + 1) l')
         end) 0 es
  end.

Definition quiet_ctx : ros_context unit := mkctx (fun _ => []) (fun _ => 0%Z) tt (fun s u => (s, u)) Ros1.

(** Run [run_all] ([ros_ok] answers false at once), then render every
    global variable, in the order of [prog_defs]. *)
Definition interp_dump : string :=
  match run_program 1000 the_program quiet_ctx 0 with
  | Some (_, v, m, _) =>
      concat_lines
        (("result = " ++ render_val v)
           :: flat_map (fun d =>
                          match d with
                          | (x, Gvar _) =>
                              match find_var (globalenv the_program) x with
                              | Some (b, _) =>
                                  match load_path m b [] with
                                  | Some mv => render_mval x mv
                                  | None => [x ++ " = unreadable"]
                                  end
                              | None => [x ++ " = missing"]
                              end
                          | _ => []
                          end) (prog_defs the_program))
  | None => "stuck"
  end.

(** ** Printed forms *)

Example print_int_min: print_expr (ci (-2147483648) tint) = "(-2147483647 - 1)".
Proof. reflexivity. Qed.
Example print_int_wrap: print_expr (ci 2147483648 tint) = "(-2147483647 - 1)".
Proof. reflexivity. Qed.
Example print_llong_min:
  print_expr (cl (-9223372036854775808) tlong) = "(-9223372036854775807LL - 1)".
Proof. reflexivity. Qed.
Example print_uint: print_expr (ci (-1) tuint) = "4294967295U".
Proof. reflexivity. Qed.
Example print_ullong: print_expr (cl (-1) tulong) = "18446744073709551615ULL".
Proof. reflexivity. Qed.
Example print_uchar: print_expr (ci 300 tuchar) = "44".
Proof. reflexivity. Qed.
Example print_neg_zero: print_expr (cd 0x8000000000000000) = "-0x0p+0".
Proof. vm_compute. reflexivity. Qed.
Example print_subnormal: print_expr (cd 1) = "0x1p-1074".
Proof. vm_compute. reflexivity. Qed.
Example print_tenth: print_expr (cd 0x3FB999999999999A) = "0x1.999999999999ap-4".
Proof. vm_compute. reflexivity. Qed.
Example print_three: print_expr (cd 0x4008000000000000) = "0x1.8p+1".
Proof. vm_compute. reflexivity. Qed.
Example print_float_tenth: print_expr (cf 0x3DCCCCCD) = "0x1.99999ap-4f".
Proof. vm_compute. reflexivity. Qed.
Example print_inf:
  print_expr (cd 0x7FF0000000000000) = "rosgen_f64_of_bits(0x7ff0000000000000ULL)".
Proof. vm_compute. reflexivity. Qed.

(** Figure 11's form of a field of a dereferenced pointer. *)
Example print_deref_field:
  print_expr (fld (fld (Ederef msg tM) "lin" tV) "x" tdouble) = "(*msg).lin.x".
Proof. reflexivity. Qed.
Example print_addrof_field:
  print_expr (Eaddrof (fld (Ederef msg tM) "lin" tV) (tptr tV)) = "&(*msg).lin".
Proof. reflexivity. Qed.

(** Operations: always parenthesised, never the token [--]. *)
Example print_binop:
  print_expr (bop Osub (bop Omul (tv "a" tint) (tv "b" tint) tint) (ci (-3) tint) tint)
  = "((a * b) - -3)".
Proof. reflexivity. Qed.
Example print_neg_neg:
  print_expr (uop Oneg (uop Oneg (tv "x" tdouble) tdouble) tdouble) = "(-(-x))".
Proof. reflexivity. Qed.
Example print_neg_const:
  print_expr (uop Oneg (ci (-3) tint) tint) = "(-(-3))".
Proof. reflexivity. Qed.
Example print_fabs:
  print_expr (uop Oabsfloat (Ecast (tv "f" tfloat) tfloat) tfloat) = "rosgen_fabsf((float)f)".
Proof. reflexivity. Qed.
Example print_cmp_not:
  print_expr (uop Onotbool (bop Ole (tv "x" tdouble) (tv "y" tdouble) tint) tint) = "(!(x <= y))".
Proof. reflexivity. Qed.

(** The semantics is stuck on C's undefined behaviour and on operands
    the typing rules refuse. *)
Definition ev (a : expr) : option val :=
  eval_expr (mkgenv [] [] []) [] [("a", Vint (-2147483648)); ("b", Vint 0); ("u", Vint 5);
                                  ("c", Vint 3)] empty a.
Example int_min_div: ev (bop Odiv (tv "a" tint) (ci (-1) tint) tint) = None.
Proof. reflexivity. Qed.
Example int_min_mod: ev (bop Omod (tv "a" tint) (ci (-1) tint) tint) = None.
Proof. reflexivity. Qed.
Example div_zero: ev (bop Odiv (tv "u" tuint) (tv "b" tuint) tuint) = None.
Proof. reflexivity. Qed.
Example neg_int_min: ev (uop Oneg (tv "a" tint) tint) = None.
Proof. reflexivity. Qed.
Example add_overflow: ev (bop Osub (tv "a" tint) (ci 1 tint) tint) = None.
Proof. reflexivity. Qed.
Example uchar_operands: ev (bop Oadd (tv "c" tuchar) (tv "c" tuchar) tuchar) = None.
Proof. reflexivity. Qed.
Example mixed_operands: ev (bop Oadd (tv "c" tint) (tv "u" tuint) tuint) = None.
Proof. reflexivity. Qed.
Example cmp_result_type: ev (bop Olt (tv "c" tint) (tv "c" tint) tuint) = None.
Proof. reflexivity. Qed.
Example unsigned_wraps: ev (bop Osub (tv "b" tuint) (tv "u" tuint) tuint) = Some (Vint 4294967291).
Proof. reflexivity. Qed.

(** Declarators. *)
Example decl_array: decl (Tarray tdouble 36) "covariance" false = "double covariance[36]".
Proof. reflexivity. Qed.
Example decl_fun_ptr:
  decl (tptr (fnty [tptr tM] Tvoid)) "cb" false = "void (*cb)(struct Msg *)".
Proof. reflexivity. Qed.
Example decl_ptr_array: decl (tptr (Tarray tint 3)) "p" false = "int (*p)[3]".
Proof. reflexivity. Qed.
Example decl_proto:
  decl (fnty [tptr (fnty [tptr tM] Tvoid)] Tvoid) "ros_subscribe_t" false
  = "void ros_subscribe_t(void (*)(struct Msg *))".
Proof. reflexivity. Qed.

(** Structs are printed after the structs they contain. *)
Example sort_structs_deps:
  map co_name (sort_structs [comp_M; Composite "Other" [("m", Tarray tM 2)]; comp_V])
  = ["Vec3"; "Msg"; "Other"].
Proof. reflexivity. Qed.
