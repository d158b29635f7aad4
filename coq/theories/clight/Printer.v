(** * Printing the Clight subset as C text *)

(** [print_program externs p] is the C11 translation unit of [p], in the
    style of the paper's Figures 8 and 11.  It is checked against a dump
    of the abstract syntax tree of [p] as S-expressions
    ([Dump.print_sexp]: parse the C with pycparser, compare the two
    trees), which is printed by a path of its own: [Dump] does not import
    this file and shares no function with it, so an error of this printer
    does not hide in the same error of the dump.

    The printer is trusted: it is not proved.  It is kept as small and
    regular as possible, and each of its outputs is checked by tests
    (gcc with [-std=c11 -pedantic -Werror], runs of the compiled code,
    comparison with the dump).  The text is built as lists of lines and
    joined once at the end, so that extraction to OCaml prints even very
    large programs in linear time (see [coq/extraction/]).

    ** The C text

    In order: a header comment; the struct definitions of [prog_types],
    each after the structs it contains by value; the helper functions for
    non-finite float constants (only if one occurs); the global variables
    (those named in [externs] are declared [extern]: they are defined
    elsewhere, e.g. [Controller_U] / [Controller_Y] in the controller's own
    C file); the prototypes of the external functions; the prototypes of
    the internal functions; the definitions of the internal functions.
    Within each group, definitions keep their order in [prog_defs].

    Function bodies: one line per local declaration ([fn_vars], then
    [fn_temps]), then one line per simple statement, four spaces of
    indentation per block.  Sequences are flattened and [Sskip] prints
    nothing.  Two statement forms are printed with sugar:
    - [Sloop (Ssequence (Sifthenelse c Sskip Sbreak) s)] (= [Swhile c s])
      prints as [while (c) { s }]; any other [Sloop s] as [for (;;) { s }];
    - [Sifthenelse c s1 Sskip] prints without its [else] branch.

    Expressions carry their C precedence and are parenthesised only where C
    requires it: [Efield (Ederef (Etempvar msg _) _) f _] prints as
    [( *msg).f] (without the space), as in Figure 11.

    Constants denote exactly the value that the semantics gives them:
    - [Econst_int n (Tint sz sg)] is [n] wrapped to [sz]/[sg] (two's
      complement), printed in decimal; [U] suffix for [unsigned int];
      [INT_MIN] is printed [(-2147483647 - 1)].  8- and 16-bit constants
      are printed as [int] constants of the wrapped value (C has no
      literals of those types; the value converts exactly);
    - [Econst_long n (Tlong sg)]: the same on 64 bits, suffixes [LL] and
      [ULL], [LLONG_MIN] printed [(-9223372036854775807LL - 1)];
    - [Econst_float] / [Econst_single] with a finite value: C99 hexadecimal
      floating constants, normalised with a leading [1] as [printf("%a")]
      does ([0x1.8p+1], [0x1p-1074], [-0x0p+0]; [f] suffix for [float]),
      which are exact;
    - non-finite values (infinities, NaNs with their payload) print as
      [rosgen_f64_of_bits(0x7ff0000000000000ULL)] /
      [rosgen_f32_of_bits(0x7fc00000U)], calls to two small [static]
      functions that reinterpret the bit pattern through a union (well
      defined in C11); they are emitted only when used;
    - operations are always parenthesised: [(e1 + e2)], [(-e)] (and
      [(-(-1))]: never the token [--]), [(!e)]; [Oabsfloat] prints as a
      call of the [static] helper [rosgen_fabs] ([double]) or
      [rosgen_fabsf] ([float]), which clears the sign bit through a
      union, emitted only when used (after the two above);
    - a constant whose type annotation is not the type of its kind (e.g.
      [Econst_int 0 (tptr t)]) prints as a cast of the constant to that
      type, the constant itself being read as [int], [long long],
      [double] or [float] respectively.

    Identifiers are printed as they are: the front end and the generator
    only produce C identifiers that are not C keywords. *)

From Coq Require Import String Ascii List ZArith Bool.
From Coq Require Strings.Byte.
From Flocq Require Import IEEE754.Binary IEEE754.Bits.
From ROSGen Require Import Syntax.
Import ListNotations.

Local Open Scope string_scope.
Local Open Scope Z_scope.

(** ** Text utilities *)

(** A line feed. *)
Definition newline : string := String (ascii_of_byte Byte.x0a) EmptyString.
(** The characters that [escape] escapes. *)
Definition dquote_char : ascii := ascii_of_byte Byte.x22.
Definition backslash_char : ascii := ascii_of_byte Byte.x5c.

(** Join lines, each followed by a newline. *)
Definition concat_lines (l : list string) : string :=
  String.concat "" (map (fun s => s ++ newline) l).

(** [sep]-separated concatenation. *)
Definition join (sep : string) (l : list string) : string := String.concat sep l.

(** One digit, in base up to 16. *)
Definition digit (d : Z) : string :=
  match d with
  | 0 => "0" | 1 => "1" | 2 => "2" | 3 => "3" | 4 => "4" | 5 => "5" | 6 => "6"
  | 7 => "7" | 8 => "8" | 9 => "9" | 10 => "a" | 11 => "b" | 12 => "c"
  | 13 => "d" | 14 => "e" | 15 => "f" | _ => "?"
  end.

(** The digits of [n >= 0] in base [b], at least [w] of them (zero
    padding), in front of [acc].  [fuel] bounds the number of digits. *)
Fixpoint digits_rec (fuel : nat) (b : Z) (w : Z) (n : Z) (acc : string) : string :=
  match fuel with
  | O => acc
  | S fuel' =>
      let acc' := digit (n mod b) ++ acc in
      let q := n / b in
      if (q =? 0) && (w <=? 1) then acc' else digits_rec fuel' b (w - 1) q acc'
  end.

(** Enough fuel for [digits_rec]: [w] plus the number of bits of [n]. *)
Definition digits_fuel (w n : Z) : nat :=
  (Z.to_nat w + match n with Zpos p => Pos.size_nat p | _ => 1 end)%nat.

(** [n >= 0] in decimal. *)
Definition string_of_nonneg (n : Z) : string := digits_rec (digits_fuel 1 n) 10 1 n "".

(** [n] in decimal, with a [-] sign if negative. *)
Definition string_of_Z (n : Z) : string :=
  if n <? 0 then "-" ++ string_of_nonneg (- n) else string_of_nonneg n.

(** [n >= 0] in hexadecimal on at least [w] digits, without prefix. *)
Definition hex_digits (w n : Z) : string := digits_rec (digits_fuel w n) 16 w n "".

(** An exponent with its sign: [+3], [-1074], [+0]. *)
Definition string_of_exponent (e : Z) : string :=
  if e <? 0 then "-" ++ string_of_nonneg (- e) else "+" ++ string_of_nonneg e.

(** ** Constants *)

(** Expressions are printed together with their precedence level:
    [3] postfix or primary, [2] unary, [1] cast, [0] any expression. *)
Definition doc : Type := (string * nat)%type.

(** Wrap in parentheses if the level is below the one required. *)
Definition at_level (need : nat) (d : doc) : string :=
  if Nat.ltb (snd d) need then "(" ++ fst d ++ ")" else fst d.

(** Wrap-around of [n] to an unsigned [bits]-bit value. *)
Definition wrap_unsigned (bits : Z) (n : Z) : Z := n mod 2 ^ bits.
(** Two's complement wrap-around of [n] to a signed [bits]-bit value. *)
Definition wrap_signed (bits : Z) (n : Z) : Z :=
  let u := n mod 2 ^ bits in if u <? 2 ^ (bits - 1) then u else u - 2 ^ bits.

(** The width of an integer type. *)
Definition intsize_bits (sz : intsize) : Z :=
  match sz with I8 => 8 | I16 => 16 | I32 => 32 end.

(** A signed integer constant with suffix [sfx] ([""] or ["LL"]) whose
    value [v] is in the range of a [bits]-bit signed type. *)
Definition signed_const (bits : Z) (sfx : string) (v : Z) : doc :=
  if v =? - 2 ^ (bits - 1) then
    ("(-" ++ string_of_nonneg (2 ^ (bits - 1) - 1) ++ sfx ++ " - 1)", 3%nat)
  else if v <? 0 then ("-" ++ string_of_nonneg (- v) ++ sfx, 2%nat)
  else (string_of_nonneg v ++ sfx, 3%nat).

(** [m * 2^e], [m > 0], as a normalised hexadecimal floating constant
    [0x1.<fraction>p<exponent>] (trailing zero digits dropped). *)
Definition hex_of_finite (m : positive) (e : Z) : string :=
  let d := Zpos (Pos.size m) in        (* bits of [m] *)
  let nb := d - 1 in                  (* bits after the leading 1 *)
  let pad := (4 - nb mod 4) mod 4 in
  let frac := (Zpos m - 2 ^ nb) * 2 ^ pad in
  let k := (nb + pad) / 4 in          (* hex digits of the fraction *)
  let fix strip (fuel : nat) (f k : Z) : Z * Z :=
    match fuel with
    | O => (f, k)
    | S fuel' => if (0 <? k) && (f mod 16 =? 0) then strip fuel' (f / 16) (k - 1) else (f, k)
    end in
  let (f, k) := strip (Z.to_nat k) frac k in
  "0x1" ++ (if k =? 0 then "" else "." ++ hex_digits k f)
        ++ "p" ++ string_of_exponent (e + nb).

(** A finite float [(-1)^s * m * 2^e], with the suffix [sfx]. *)
Definition finite_const (s : bool) (m : positive) (e : Z) (sfx : string) : doc :=
  if s then ("-" ++ hex_of_finite m e ++ sfx, 2%nat) else (hex_of_finite m e ++ sfx, 3%nat).

(** A zero of sign [s], with the suffix [sfx]. *)
Definition zero_const (s : bool) (sfx : string) : doc :=
  if s then ("-0x0p+0" ++ sfx, 2%nat) else ("0x0p+0" ++ sfx, 3%nat).

(** The names of the helpers for non-finite constants. *)
Definition f64_helper : string := "rosgen_f64_of_bits".
Definition f32_helper : string := "rosgen_f32_of_bits".
(** The helpers of [Oabsfloat]: the sign bit cleared through a union. *)
Definition fabs_helper : string := "rosgen_fabs".
Definition fabsf_helper : string := "rosgen_fabsf".

(** A [double] constant: hexadecimal if finite, through the helper otherwise. *)
Definition float64_const (f : float64) : doc :=
  match f with
  | B754_zero _ _ s => zero_const s ""
  | B754_finite _ _ s m e _ => finite_const s m e ""
  | _ => (f64_helper ++ "(0x" ++ hex_digits 16 (bits_of_b64 f) ++ "ULL)", 3%nat)
  end.

(** A [float] constant: hexadecimal if finite, through the helper otherwise. *)
Definition float32_const (f : float32) : doc :=
  match f with
  | B754_zero _ _ s => zero_const s "f"
  | B754_finite _ _ s m e _ => finite_const s m e "f"
  | _ => (f32_helper ++ "(0x" ++ hex_digits 8 (bits_of_b32 f) ++ "U)", 3%nat)
  end.

(** Zeros and finite numbers, as opposed to infinities and NaNs. *)
Definition is_finite64 (f : float64) : bool :=
  match f with B754_zero _ _ _ | B754_finite _ _ _ _ _ _ => true | _ => false end.
Definition is_finite32 (f : float32) : bool :=
  match f with B754_zero _ _ _ | B754_finite _ _ _ _ _ _ => true | _ => false end.

(** ** Types and declarators *)

Definition int_type_name (sz : intsize) (sg : signedness) : string :=
  match sz, sg with
  | I8, Signed => "signed char"
  | I8, Unsigned => "unsigned char"
  | I16, Signed => "short"
  | I16, Unsigned => "unsigned short"
  | I32, Signed => "int"
  | I32, Unsigned => "unsigned int"
  end.

(** [x] preceded by a space, unless empty. *)
Definition space_before (x : string) : string :=
  match x with EmptyString => "" | _ => " " ++ x end.

(** [decl ty d isptr] declares [d] with type [ty]: [d] is the declarator
    built so far ([""] for an abstract declarator, as in casts and
    prototypes of external functions), and [isptr] tells whether it begins
    with a [*], in which case array and function suffixes need
    parentheses: [int ( *p)[3]], [void ( *cb)(struct T * )]. *)
Fixpoint decl (ty : type) (d : string) (isptr : bool) {struct ty} : string :=
  let wrap := if isptr then "(" ++ d ++ ")" else d in
  match ty with
  | Tvoid => "void" ++ space_before d
  | Tint sz sg => int_type_name sz sg ++ space_before d
  | Tlong Signed => "long long" ++ space_before d
  | Tlong Unsigned => "unsigned long long" ++ space_before d
  | Tfloat F32 => "float" ++ space_before d
  | Tfloat F64 => "double" ++ space_before d
  | Tpointer t => decl t ("*" ++ d) true
  | Tarray t n => decl t (wrap ++ "[" ++ string_of_Z n ++ "]") false
  | Tfunction args res =>
      let fix params (l : list type) : string :=
        match l with
        | [] => ""
        | [t] => decl t "" false
        | t :: l' => decl t "" false ++ ", " ++ params l'
        end in
      let ps := match args with [] => "void" | _ => params args end in
      decl res (wrap ++ "(" ++ ps ++ ")") false
  | Tstruct id => "struct " ++ id ++ space_before d
  end.

(** The type name of [ty], as in a cast: [struct T *]. *)
Definition type_name (ty : type) : string := decl ty "" false.

(** ** Expressions *)

(** A constant [c] of the kind's own type is printed as is; of another
    type, as a cast. *)
Definition cast_if (ok : bool) (ty : type) (c : doc) : doc :=
  if ok then c else ("(" ++ type_name ty ++ ")" ++ at_level 1 c, 1%nat).

(** An [Econst_int]: wrapped to its type, [U] suffix for [unsigned int]. *)
Definition int_const (n : Z) (ty : type) : doc :=
  match ty with
  | Tint I32 Unsigned => (string_of_nonneg (wrap_unsigned 32 n) ++ "U", 3%nat)
  | Tint sz Unsigned => signed_const 32 "" (wrap_unsigned (intsize_bits sz) n)
  | Tint sz Signed => signed_const 32 "" (wrap_signed (intsize_bits sz) n)
  | _ => cast_if false ty (signed_const 32 "" (wrap_signed 32 n))
  end.

(** An [Econst_long]: wrapped to 64 bits, [LL] or [ULL] suffix. *)
Definition long_const (n : Z) (ty : type) : doc :=
  match ty with
  | Tlong Unsigned => (string_of_nonneg (wrap_unsigned 64 n) ++ "ULL", 3%nat)
  | Tlong Signed => signed_const 64 "LL" (wrap_signed 64 n)
  | _ => cast_if false ty (signed_const 64 "LL" (wrap_signed 64 n))
  end.

(** Whether [ty] is the floating type of size [fs]. *)
Definition is_tfloat (fs : floatsize) (ty : type) : bool :=
  match ty, fs with Tfloat F64, F64 | Tfloat F32, F32 => true | _, _ => false end.

(** The C token of a binary operator. *)
Definition binop_token (op : binary_operation) : string :=
  match op with
  | Oadd => "+" | Osub => "-" | Omul => "*" | Odiv => "/" | Omod => "%"
  | Oand => "&" | Oor => "|" | Oxor => "^"
  | Oeq => "==" | One => "!=" | Olt => "<" | Ogt => ">" | Ole => "<=" | Oge => ">="
  end.

(** Whether the operand of an [Oabsfloat] is a [float] (else a [double]). *)
Definition is_single_expr (e : expr) : bool := is_tfloat F32 (typeof e).

(** [e] with its precedence level.  An operation is always printed in
    parentheses, [(e1 + e2)], [(-e)], [(!e)]: no precedence or
    associativity rule of C is involved in reading it back. *)
Fixpoint expr_doc (e : expr) : doc :=
  match e with
  | Econst_int n ty => int_const n ty
  | Econst_long n ty => long_const n ty
  | Econst_float f ty => cast_if (is_tfloat F64 ty) ty (float64_const f)
  | Econst_single f ty => cast_if (is_tfloat F32 ty) ty (float32_const f)
  | Evar x _ => (x, 3%nat)
  | Etempvar x _ => (x, 3%nat)
  | Ederef e1 _ => ("*" ++ at_level 1 (expr_doc e1), 2%nat)
  | Eaddrof e1 _ =>
      let s := at_level 1 (expr_doc e1) in
      (* [& &x] must not become the token [&&] *)
      ("&" ++ (if String.prefix "&" s then "(" ++ s ++ ")" else s), 2%nat)
  | Efield e1 f _ => (at_level 3 (expr_doc e1) ++ "." ++ f, 3%nat)
  | Eindex e1 e2 _ => (at_level 3 (expr_doc e1) ++ "[" ++ fst (expr_doc e2) ++ "]", 3%nat)
  | Ecast e1 ty => ("(" ++ type_name ty ++ ")" ++ at_level 1 (expr_doc e1), 1%nat)
  | Eunop op e1 _ =>
      let s := at_level 1 (expr_doc e1) in
      match op with
      | Oneg =>
          (* [- -x] must not become the token [--] *)
          ("(-" ++ (if String.prefix "-" s then "(" ++ s ++ ")" else s) ++ ")", 3%nat)
      | Onotbool => ("(!" ++ s ++ ")", 3%nat)
      | Oabsfloat =>
          ((if is_single_expr e1 then fabsf_helper else fabs_helper)
             ++ "(" ++ fst (expr_doc e1) ++ ")", 3%nat)
      end
  | Ebinop op e1 e2 _ =>
      ("(" ++ at_level 1 (expr_doc e1) ++ " " ++ binop_token op ++ " "
           ++ at_level 1 (expr_doc e2) ++ ")", 3%nat)
  end.

(** [e] as a full expression. *)
Definition print_expr (e : expr) : string := fst (expr_doc e).

(** [f(a1, ..., an)]. *)
Definition print_call (f : expr) (args : list expr) : string :=
  at_level 3 (expr_doc f) ++ "(" ++ join ", " (map print_expr args) ++ ")".

(** ** Statements *)

Definition indent_step : string := "    ".

(** The lines of [s] at indentation [ind], in front of the lines [k]. *)
Fixpoint stmt_lines (ind : string) (s : statement) (k : list string) {struct s}
  : list string :=
  match s with
  | Sskip => k
  | Sassign lhs rhs => (ind ++ print_expr lhs ++ " = " ++ print_expr rhs ++ ";") :: k
  | Sset x e => (ind ++ x ++ " = " ++ print_expr e ++ ";") :: k
  | Scall None f args => (ind ++ print_call f args ++ ";") :: k
  | Scall (Some x) f args => (ind ++ x ++ " = " ++ print_call f args ++ ";") :: k
  | Ssequence s1 s2 => stmt_lines ind s1 (stmt_lines ind s2 k)
  | Sifthenelse c s1 Sskip =>
      (ind ++ "if (" ++ print_expr c ++ ") {")
        :: stmt_lines (ind ++ indent_step) s1 ((ind ++ "}") :: k)
  | Sifthenelse c s1 s2 =>
      (ind ++ "if (" ++ print_expr c ++ ") {")
        :: stmt_lines (ind ++ indent_step) s1
             ((ind ++ "} else {")
                :: stmt_lines (ind ++ indent_step) s2 ((ind ++ "}") :: k))
  | Sloop (Ssequence (Sifthenelse c Sskip Sbreak) body) =>
      (ind ++ "while (" ++ print_expr c ++ ") {")
        :: stmt_lines (ind ++ indent_step) body ((ind ++ "}") :: k)
  | Sloop body =>
      (ind ++ "for (;;) {") :: stmt_lines (ind ++ indent_step) body ((ind ++ "}") :: k)
  | Sbreak => (ind ++ "break;") :: k
  | Sreturn None => (ind ++ "return;") :: k
  | Sreturn (Some e) => (ind ++ "return " ++ print_expr e ++ ";") :: k
  end.

(** ** Functions and programs *)

(** The declarator of a function with named parameters:
    [void cb(struct T *msg)]. *)
Definition function_header (id : ident) (f : function) : string :=
  let ps := match fn_params f with
            | [] => "void"
            | l => join ", " (map (fun xt => decl (snd xt) (fst xt) false) l)
            end in
  decl (fn_return f) (id ++ "(" ++ ps ++ ")") false.

(** Local declarations, one per line. *)
Definition decl_lines (ind : string) (l : list (ident * type)) (k : list string) : list string :=
  fold_right (fun xt k => (ind ++ decl (snd xt) (fst xt) false ++ ";") :: k) k l.

(** A function definition, in the style of Figure 11. *)
Definition function_lines (id : ident) (f : function) (k : list string) : list string :=
  function_header id f
    :: "{"
    :: decl_lines indent_step (fn_vars f)
         (decl_lines indent_step (fn_temps f)
            (stmt_lines indent_step (fn_body f) ("}" :: "" :: k))).

(** A struct definition, one member per line. *)
Definition struct_lines (co : composite_definition) (k : list string) : list string :=
  ("struct " ++ co_name co ++ " {")
    :: decl_lines indent_step (co_members co) ("};" :: "" :: k).

(** *** Struct order *)

(** The structs that a member of type [ty] contains by value. *)
Fixpoint struct_deps (ty : type) : list ident :=
  match ty with
  | Tstruct id => [id]
  | Tarray t _ => struct_deps t
  | _ => []
  end.

(** Membership of an identifier in a list. *)
Definition mem_ident (x : ident) (l : list ident) : bool := existsb (String.eqb x) l.

(** Depth-first: the structs that [id] contains come before [id].  The
    state is the output (reversed) and the names already visited. *)
Fixpoint visit_struct (fuel : nat) (all : list composite_definition) (id : ident)
  (st : list composite_definition * list ident) : list composite_definition * list ident :=
  match fuel with
  | O => st
  | S fuel' =>
      if mem_ident id (snd st) then st else
      match find_composite id all with
      | None => st
      | Some co =>
          let st1 := (fst st, id :: snd st) in
          let deps := flat_map (fun m => struct_deps (snd m)) (co_members co) in
          let st2 := fold_left (fun st' d => visit_struct fuel' all d st') deps st1 in
          (co :: fst st2, snd st2)
      end
  end.

(** [prog_types] in dependency order (otherwise in their given order). *)
Definition sort_structs (l : list composite_definition) : list composite_definition :=
  rev (fst (fold_left (fun st co => visit_struct (S (length l)) l (co_name co) st)
                      l ([], []))).

(** *** Helper functions *)

(** The [static] helpers a program needs: [rosgen_f64_of_bits] /
    [rosgen_f32_of_bits] for its non-finite [double] / [float] constants,
    [rosgen_fabs] / [rosgen_fabsf] for its [Oabsfloat]s. *)
Record needs : Type := mkneeds {
  need_f64 : bool; need_f32 : bool; need_fabs : bool; need_fabsf : bool
}.

Definition no_needs : needs := mkneeds false false false false.

(** Pointwise disjunction. *)
Definition or_needs (x y : needs) : needs :=
  mkneeds (need_f64 x || need_f64 y) (need_f32 x || need_f32 y)
          (need_fabs x || need_fabs y) (need_fabsf x || need_fabsf y).

Fixpoint expr_needs (e : expr) : needs :=
  match e with
  | Econst_float f _ => mkneeds (negb (is_finite64 f)) false false false
  | Econst_single f _ => mkneeds false (negb (is_finite32 f)) false false
  | Econst_int _ _ | Econst_long _ _ | Evar _ _ | Etempvar _ _ => no_needs
  | Ederef e1 _ | Eaddrof e1 _ | Efield e1 _ _ | Ecast e1 _ => expr_needs e1
  | Eunop Oabsfloat e1 _ =>
      or_needs (expr_needs e1)
               (if is_single_expr e1 then mkneeds false false false true
                else mkneeds false false true false)
  | Eunop _ e1 _ => expr_needs e1
  | Eindex e1 e2 _ | Ebinop _ e1 e2 _ => or_needs (expr_needs e1) (expr_needs e2)
  end.

(** The same for the expressions of a statement. *)
Fixpoint stmt_needs (s : statement) : needs :=
  match s with
  | Sskip | Sbreak | Sreturn None => no_needs
  | Sassign e1 e2 => or_needs (expr_needs e1) (expr_needs e2)
  | Sset _ e | Sreturn (Some e) => expr_needs e
  | Scall _ f args => fold_left (fun acc a => or_needs acc (expr_needs a)) args (expr_needs f)
  | Ssequence s1 s2 => or_needs (stmt_needs s1) (stmt_needs s2)
  | Sifthenelse c s1 s2 => or_needs (expr_needs c) (or_needs (stmt_needs s1) (stmt_needs s2))
  | Sloop s1 => stmt_needs s1
  end.

(** The helpers the functions of [p] need. *)
Definition prog_needs (p : program) : needs :=
  fold_left (fun acc d =>
               match snd d with
               | Gfun (Internal f) => or_needs acc (stmt_needs (fn_body f))
               | _ => acc
               end) (prog_defs p) no_needs.

(** The helpers' definitions, those [need]ed, in this order. *)
Definition helper_lines (need : needs) : list string :=
  (if need_f64 need then
     [ "static double " ++ f64_helper ++ "(unsigned long long b)";
       "{";
       "    union { unsigned long long u; double d; } x;";
       "    x.u = b;";
       "    return x.d;";
       "}";
       "" ]
   else [])
  ++ (if need_f32 need then
     [ "static float " ++ f32_helper ++ "(unsigned int b)";
       "{";
       "    union { unsigned int u; float f; } x;";
       "    x.u = b;";
       "    return x.f;";
       "}";
       "" ]
   else [])
  ++ (if need_fabs need then
     [ "static double " ++ fabs_helper ++ "(double d)";
       "{";
       "    union { unsigned long long u; double d; } x;";
       "    x.d = d;";
       "    x.u &= 0x7fffffffffffffffULL;";
       "    return x.d;";
       "}";
       "" ]
   else [])
  ++ (if need_fabsf need then
     [ "static float " ++ fabsf_helper ++ "(float f)";
       "{";
       "    union { unsigned int u; float f; } x;";
       "    x.f = f;";
       "    x.u &= 0x7fffffffU;";
       "    return x.f;";
       "}";
       "" ]
   else []).

(** *** The translation unit *)

Definition header_lines : list string :=
  [ "/* Generated by pyrosgen from a Clight AST (ROSGen.Printer.print_program).";
    "   Do not edit: the proofs are about the AST this text was printed from. */";
    "" ].

(** Global variables: definitions, or [extern] declarations for [externs]. *)
Definition global_lines (externs : list ident) (defs : list (ident * globdef))
  : list string :=
  fold_right (fun d k =>
                match snd d with
                | Gvar ty =>
                    ((if mem_ident (fst d) externs then "extern " else "")
                       ++ decl ty (fst d) false ++ ";") :: k
                | _ => k
                end) [] defs.

(** Prototypes of the external functions (parameters unnamed). *)
Definition external_proto_lines (defs : list (ident * globdef)) : list string :=
  fold_right (fun d k =>
                match snd d with
                | Gfun (External _ params res) =>
                    (decl (Tfunction params res) (fst d) false ++ ";") :: k
                | _ => k
                end) [] defs.

(** Prototypes of the internal functions (parameters named). *)
Definition internal_proto_lines (defs : list (ident * globdef)) : list string :=
  fold_right (fun d k =>
                match snd d with
                | Gfun (Internal f) => (function_header (fst d) f ++ ";") :: k
                | _ => k
                end) [] defs.

(** Definitions of the internal functions. *)
Definition function_def_lines (defs : list (ident * globdef)) : list string :=
  fold_right (fun d k =>
                match snd d with
                | Gfun (Internal f) => function_lines (fst d) f k
                | _ => k
                end) [] defs.

(** A group of lines followed by an empty line, or nothing if empty. *)
Definition section (l : list string) : list string :=
  match l with [] => [] | _ => l ++ [""] end.

(** The struct definitions of [p]: the struct section of the C text. *)
Definition struct_section_lines (p : program) : list string :=
  fold_right struct_lines [] (sort_structs (prog_types p)).

(** Everything after the structs: helpers, globals, prototypes, functions. *)
Definition code_section_lines (externs : list ident) (p : program) : list string :=
  helper_lines (prog_needs p)
  ++ section (global_lines externs (prog_defs p))
  ++ section (external_proto_lines (prog_defs p))
  ++ section (internal_proto_lines (prog_defs p))
  ++ function_def_lines (prog_defs p).

(** The lines of the C text of [p]. *)
Definition print_program_lines (externs : list ident) (p : program) : list string :=
  header_lines ++ struct_section_lines p ++ code_section_lines externs p.

(** The C text of [p]; the globals named in [externs] are declared
    [extern] instead of being defined. *)
Definition print_program (externs : list ident) (p : program) : string :=
  concat_lines (print_program_lines externs p).

(** *** Structs in a header of their own *)

(** The struct definitions of a program can be printed as a header file
    of their own, so that the C glue and the C++ wrapper over roscpp
    include one and the same text, printed from the AST:
    - [print_types p] is exactly the struct section of [print_program];
    - [print_types_header guard p] is that section in a header file
      protected by the include guard [guard];
    - [print_program_with_header hdr externs p] is [print_program externs p]
      with the struct section replaced by [#include "hdr"].
    [guard] must be a C identifier and [hdr] a file name without double
    quotes or newlines: the front end derives both from the checked node
    name. *)

Definition print_types (p : program) : string :=
  concat_lines (struct_section_lines p).

Definition types_header_lines (guard : string) (p : program) : list string :=
  [ "/* Generated by pyrosgen from a Clight AST (ROSGen.Printer.print_types).";
    "   Do not edit: the proofs are about the AST this text was printed from. */";
    "#ifndef " ++ guard;
    "#define " ++ guard;
    "" ]
  ++ struct_section_lines p
  ++ [ "#endif /* " ++ guard ++ " */" ].

Definition print_types_header (guard : string) (p : program) : string :=
  concat_lines (types_header_lines guard p).

Definition print_program_with_header_lines (hdr : string) (externs : list ident)
  (p : program) : list string :=
  header_lines
  ++ [ "#include " ++ String dquote_char (hdr ++ String dquote_char EmptyString); "" ]
  ++ code_section_lines externs p.

Definition print_program_with_header (hdr : string) (externs : list ident)
  (p : program) : string :=
  concat_lines (print_program_with_header_lines hdr externs p).

(** The C text of [p] is the header comment, the struct section (the text
    of [print_types p]) and the code; with a header, the struct section is
    replaced by the [#include] line. *)
Lemma print_program_lines_split:
  forall externs p,
  print_program_lines externs p =
  (header_lines ++ struct_section_lines p ++ code_section_lines externs p)%list.
Proof. reflexivity. Qed.

Lemma print_program_with_header_lines_split:
  forall hdr externs p,
  print_program_with_header_lines hdr externs p =
  (header_lines ++ [ ("#include """ ++ hdr ++ """")%string; "" ] ++ code_section_lines externs p)%list.
Proof. reflexivity. Qed.
