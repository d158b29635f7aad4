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
From ROSGen Require Import Syntax FloatBits Printer Values Memory Environment Semantics Typing Interp.
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
    ("ros_ok", Gfun (External EF_ros_ok [] tint));
    ("ros_subscribe_t", Gfun (External (EF_ros_subscribe "/t" "Msg" 1)
                                       [tptr (fnty [tptr tM] Tvoid)] Tvoid));
    ("ints", f_ints); ("floats", f_floats); ("copy_msg", f_copy);
    ("get_x", f_get_x); ("ret_neg", f_ret_neg); ("loops", f_loops);
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

Definition quiet_ctx : ros_context unit := mkctx (fun _ => []) tt (fun s u => (s, u)).

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
