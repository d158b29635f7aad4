(** * The S-expression dump of the Clight subset *)

(** [print_sexp externs p] is a dump of the abstract syntax tree of [p]
    as S-expressions.  The C text that [Printer.print_program] prints
    from the same AST is checked against it (the Python printer
    validation parses the C with pycparser and compares the two trees,
    DESIGN.md section 7).

    ** Independence from the C printer

    This file does not import [Printer] and shares no function with it:
    its own decimal and hexadecimal numerals (through the standard
    library's [Decimal]/[Hexadecimal] representations, not [Printer]'s
    digit loop), its own escaping, joining and line ending, its own
    spelling of every type, operator and external function.  So one
    error of the C printer (say [Olt] printed [<=]) does not also change
    the dump (which still says [lt]): the validation sees the
    disagreement and refuses the text (the test
    [tests/validation/test_printer_mutation.py] mutates [Printer.v]
    this way).  Only the AST ([Syntax]), Flocq's [bits_of_b64] /
    [bits_of_b32] and the standard library are shared.

    The dump is trusted like the printer (not proved); its bytes are
    fixed by the golden files and by the Python parser of the dump
    ([pyrosgen/proof/sexp.py]).

    ** Grammar

    Grammar of the dump (one top-level item per line, statements of
    sequences one per line; whitespace is not significant):
<<
program ::= (program (externs IDENT...) (main IDENT) item...)
item    ::= (struct IDENT (IDENT type)...)
          | (gvar IDENT type)
          | (external IDENT ef (type...) type)        params, result
          | (function IDENT type (params (IDENT type)...) (vars (IDENT type)...)
                                  (temps (IDENT type)...) (body stmt))
type    ::= void | (int SIZE SIGN) | (long SIGN) | (float FSIZE) | (ptr type)
          | (array type INT) | (fun (type...) type) | (struct IDENT)
SIZE    ::= I8 | I16 | I32       SIGN ::= signed | unsigned     FSIZE ::= F32 | F64
expr    ::= (const_int INT type) | (const_long INT type)
          | (const_float HEX64 type) | (const_single HEX32 type)
          | (var IDENT type) | (tempvar IDENT type) | (deref expr type)
          | (addrof expr type) | (field expr IDENT type) | (index expr expr type)
          | (cast expr type) | (unop UNOP expr type) | (binop BINOP expr expr type)
UNOP    ::= neg | notbool | absfloat
BINOP   ::= add | sub | mul | div | mod | and | or | xor | eq | ne | lt | gt | le | ge
stmt    ::= (skip) | (assign expr expr) | (set IDENT expr)
          | (call () expr (expr...)) | (call (IDENT) expr (expr...))
          | (seq stmt...) | (if expr stmt stmt) | (loop stmt) | (break)
          | (return) | (return expr)
ef      ::= (ros_init) | (ros_ok) | (ros_spinOnce) | (ros_now) | (ros_time_sec)
          | (ros_time_nsec) | (ros_rate_sleep INT)
          | (ros_subscribe STRING IDENT INT) | (ros_advertise STRING IDENT INT)
          | (ros_publish STRING IDENT)
          | (controller_initialize IDENT IDENT) | (controller_step IDENT IDENT)
>>
    where [X...] means zero or more [X].
    [INT] is a decimal integer (possibly negative), exactly the [Z] of the
    AST (not wrapped: the C text shows it wrapped to its type).  [HEX64] /
    [HEX32] is the IEEE bit pattern of the float, [0x] and 16 / 8 hex
    digits.  [STRING] is in double quotes, in which a double quote and a
    backslash are preceded by a backslash.
    Items are in the order of [prog_types] then [prog_defs].  [(seq ...)]
    is the flattening of a tree of [Ssequence]s (sequencing is
    associative), keeping [(skip)]s. *)

From Coq Require Import String Ascii List ZArith NArith Bool.
From Coq Require Strings.Byte.
From Flocq Require Import IEEE754.Binary IEEE754.Bits.
From ROSGen Require Import Syntax.
Import ListNotations.

Local Open Scope string_scope.
Local Open Scope Z_scope.

(** ** Text of the dump *)

(** The line feed that ends each line of the dump. *)
Definition dump_newline : string := String (ascii_of_byte Byte.x0a) EmptyString.

(** The lines [l], each followed by a line feed ([String.concat] is
    extracted to OCaml's, linear in the size of the text). *)
Definition dump_lines (l : list string) : string :=
  String.concat EmptyString (map (fun s => s ++ dump_newline) l).

(** The atoms [l], separated by single spaces. *)
Definition dump_join (l : list string) : string := String.concat " " l.

(** A decimal numeral of the standard library as text. *)
Fixpoint dump_dec (u : Decimal.uint) : string :=
  match u with
  | Decimal.Nil => EmptyString
  | Decimal.D0 u' => "0" ++ dump_dec u' | Decimal.D1 u' => "1" ++ dump_dec u'
  | Decimal.D2 u' => "2" ++ dump_dec u' | Decimal.D3 u' => "3" ++ dump_dec u'
  | Decimal.D4 u' => "4" ++ dump_dec u' | Decimal.D5 u' => "5" ++ dump_dec u'
  | Decimal.D6 u' => "6" ++ dump_dec u' | Decimal.D7 u' => "7" ++ dump_dec u'
  | Decimal.D8 u' => "8" ++ dump_dec u' | Decimal.D9 u' => "9" ++ dump_dec u'
  end.

(** [n] in decimal, [-] in front if negative (the standard library's
    [Z.to_int]). *)
Definition dump_Z (n : Z) : string :=
  match Z.to_int n with
  | Decimal.Pos u => dump_dec u
  | Decimal.Neg u => "-" ++ dump_dec u
  end.

(** A hexadecimal numeral of the standard library as text, lower case. *)
Fixpoint dump_hexadecimal (u : Hexadecimal.uint) : string :=
  match u with
  | Hexadecimal.Nil => EmptyString
  | Hexadecimal.D0 u' => "0" ++ dump_hexadecimal u' | Hexadecimal.D1 u' => "1" ++ dump_hexadecimal u'
  | Hexadecimal.D2 u' => "2" ++ dump_hexadecimal u' | Hexadecimal.D3 u' => "3" ++ dump_hexadecimal u'
  | Hexadecimal.D4 u' => "4" ++ dump_hexadecimal u' | Hexadecimal.D5 u' => "5" ++ dump_hexadecimal u'
  | Hexadecimal.D6 u' => "6" ++ dump_hexadecimal u' | Hexadecimal.D7 u' => "7" ++ dump_hexadecimal u'
  | Hexadecimal.D8 u' => "8" ++ dump_hexadecimal u' | Hexadecimal.D9 u' => "9" ++ dump_hexadecimal u'
  | Hexadecimal.Da u' => "a" ++ dump_hexadecimal u' | Hexadecimal.Db u' => "b" ++ dump_hexadecimal u'
  | Hexadecimal.Dc u' => "c" ++ dump_hexadecimal u' | Hexadecimal.Dd u' => "d" ++ dump_hexadecimal u'
  | Hexadecimal.De u' => "e" ++ dump_hexadecimal u' | Hexadecimal.Df u' => "f" ++ dump_hexadecimal u'
  end.

(** [k] zeros in front of [s]. *)
Fixpoint dump_zeros (k : nat) (s : string) : string :=
  match k with O => s | S k' => "0" ++ dump_zeros k' s end.

(** [n >= 0] in hexadecimal on at least [w] digits (zeros in front),
    without prefix: the bit pattern of a float constant. *)
Definition dump_hex (w n : Z) : string :=
  let s := dump_hexadecimal (N.to_hex_uint (Z.to_N n)) in
  dump_zeros (Z.to_nat w - String.length s) s.

(** The text of a [STRING] between its double quotes: a backslash before
    each double quote (byte 34) and backslash (byte 92). *)
Fixpoint dump_escape (s : string) : string :=
  match s with
  | EmptyString => EmptyString
  | String c s' =>
      let b := Ascii.N_of_ascii c in
      if orb (N.eqb b 34) (N.eqb b 92)
      then String (ascii_of_byte Byte.x5c) (String c (dump_escape s'))
      else String c (dump_escape s')
  end.

(** ** The dump *)

Definition sexp_list (l : list string) : string := "(" ++ dump_join l ++ ")".

(** Atoms of the dump for the parts of types. *)
Definition sexp_signedness (sg : signedness) : string :=
  match sg with Signed => "signed" | Unsigned => "unsigned" end.

(** A type in the dump. *)
Fixpoint sexp_type (ty : type) : string :=
  match ty with
  | Tvoid => "void"
  | Tint sz sg =>
      sexp_list ["int"; match sz with I8 => "I8" | I16 => "I16" | I32 => "I32" end;
                 sexp_signedness sg]
  | Tlong sg => sexp_list ["long"; sexp_signedness sg]
  | Tfloat fs => sexp_list ["float"; match fs with F32 => "F32" | F64 => "F64" end]
  | Tpointer t => sexp_list ["ptr"; sexp_type t]
  | Tarray t n => sexp_list ["array"; sexp_type t; dump_Z n]
  | Tfunction args res =>
      let fix targs (l : list type) : list string :=
        match l with [] => [] | t :: l' => sexp_type t :: targs l' end in
      sexp_list ["fun"; sexp_list (targs args); sexp_type res]
  | Tstruct id => sexp_list ["struct"; id]
  end.

(** Operators in the dump. *)
Definition sexp_unop (op : unary_operation) : string :=
  match op with Oneg => "neg" | Onotbool => "notbool" | Oabsfloat => "absfloat" end.

Definition sexp_binop (op : binary_operation) : string :=
  match op with
  | Oadd => "add" | Osub => "sub" | Omul => "mul" | Odiv => "div" | Omod => "mod"
  | Oand => "and" | Oor => "or" | Oxor => "xor"
  | Oeq => "eq" | One => "ne" | Olt => "lt" | Ogt => "gt" | Ole => "le" | Oge => "ge"
  end.

(** An expression in the dump, with its type. *)
Fixpoint sexp_expr (e : expr) : string :=
  match e with
  | Econst_int n ty => sexp_list ["const_int"; dump_Z n; sexp_type ty]
  | Econst_long n ty => sexp_list ["const_long"; dump_Z n; sexp_type ty]
  | Econst_float f ty =>
      sexp_list ["const_float"; "0x" ++ dump_hex 16 (bits_of_b64 f); sexp_type ty]
  | Econst_single f ty =>
      sexp_list ["const_single"; "0x" ++ dump_hex 8 (bits_of_b32 f); sexp_type ty]
  | Evar x ty => sexp_list ["var"; x; sexp_type ty]
  | Etempvar x ty => sexp_list ["tempvar"; x; sexp_type ty]
  | Ederef e1 ty => sexp_list ["deref"; sexp_expr e1; sexp_type ty]
  | Eaddrof e1 ty => sexp_list ["addrof"; sexp_expr e1; sexp_type ty]
  | Efield e1 f ty => sexp_list ["field"; sexp_expr e1; f; sexp_type ty]
  | Eindex e1 e2 ty => sexp_list ["index"; sexp_expr e1; sexp_expr e2; sexp_type ty]
  | Ecast e1 ty => sexp_list ["cast"; sexp_expr e1; sexp_type ty]
  | Eunop op e1 ty => sexp_list ["unop"; sexp_unop op; sexp_expr e1; sexp_type ty]
  | Ebinop op e1 e2 ty => sexp_list ["binop"; sexp_binop op; sexp_expr e1; sexp_expr e2; sexp_type ty]
  end.

(** A [STRING] of the dump. *)
Definition sexp_string (s : string) : string := """" ++ dump_escape s ++ """".

(** A natural number in decimal. *)
Definition sexp_nat (n : nat) : string := dump_Z (Z.of_nat n).

(** The meaning tag of an external function. *)
Definition sexp_ef (ef : external_function) : string :=
  match ef with
  | EF_ros_init => "(ros_init)"
  | EF_ros_ok => "(ros_ok)"
  | EF_ros_spinOnce => "(ros_spinOnce)"
  | EF_ros_now => "(ros_now)"
  | EF_ros_time_sec => "(ros_time_sec)"
  | EF_ros_time_nsec => "(ros_time_nsec)"
  | EF_ros_rate_sleep p => sexp_list ["ros_rate_sleep"; dump_Z p]
  | EF_ros_subscribe t m q => sexp_list ["ros_subscribe"; sexp_string t; m; sexp_nat q]
  | EF_ros_advertise t m q => sexp_list ["ros_advertise"; sexp_string t; m; sexp_nat q]
  | EF_ros_publish t m => sexp_list ["ros_publish"; sexp_string t; m]
  | EF_controller_initialize u y => sexp_list ["controller_initialize"; u; y]
  | EF_controller_step u y => sexp_list ["controller_step"; u; y]
  end.

(** Statements, one simple statement per line.  A compound statement opens
    on its line, its sub-statements follow one level deeper, and its
    closing parenthesis ends the line of its last sub-statement ([close]
    is what that line must end with).  [inseq] holds for the elements of
    a sequence that is already open: their own [Ssequence]s are not opened
    again, which flattens trees of sequences. *)
Fixpoint sexp_stmt_lines (inseq : bool) (ind close : string) (s : statement)
  (k : list string) {struct s} : list string :=
  let ind' := ind ++ "  " in
  match s with
  | Sskip => (ind ++ "(skip)" ++ close) :: k
  | Sassign e1 e2 => (ind ++ sexp_list ["assign"; sexp_expr e1; sexp_expr e2] ++ close) :: k
  | Sset x e => (ind ++ sexp_list ["set"; x; sexp_expr e] ++ close) :: k
  | Scall r f args =>
      (ind ++ sexp_list ["call"; match r with None => "()" | Some x => "(" ++ x ++ ")" end;
                         sexp_expr f; sexp_list (map sexp_expr args)] ++ close) :: k
  | Ssequence s1 s2 =>
      if inseq then
        sexp_stmt_lines true ind "" s1 (sexp_stmt_lines true ind close s2 k)
      else
        (ind ++ "(seq")
          :: sexp_stmt_lines true ind' "" s1 (sexp_stmt_lines true ind' (")" ++ close) s2 k)
  | Sifthenelse c s1 s2 =>
      (ind ++ "(if " ++ sexp_expr c)
        :: sexp_stmt_lines false ind' "" s1 (sexp_stmt_lines false ind' (")" ++ close) s2 k)
  | Sloop s1 => (ind ++ "(loop") :: sexp_stmt_lines false ind' (")" ++ close) s1 k
  | Sbreak => (ind ++ "(break)" ++ close) :: k
  | Sreturn None => (ind ++ "(return)" ++ close) :: k
  | Sreturn (Some e) => (ind ++ sexp_list ["return"; sexp_expr e] ++ close) :: k
  end.

(** A name with its type: [(x T)]. *)
Definition sexp_binding (xt : ident * type) : string := sexp_list [fst xt; sexp_type (snd xt)].

(** A global definition in the dump. *)
Definition sexp_def_lines (d : ident * globdef) (k : list string) : list string :=
  let (id, g) := d in
  match g with
  | Gvar ty => sexp_list ["gvar"; id; sexp_type ty] :: k
  | Gfun (External ef params res) =>
      sexp_list ["external"; id; sexp_ef ef; sexp_list (map sexp_type params); sexp_type res]
        :: k
  | Gfun (Internal f) =>
      ("(function " ++ id ++ " " ++ sexp_type (fn_return f))
        :: ("  " ++ sexp_list ("params" :: map sexp_binding (fn_params f)))
        :: ("  " ++ sexp_list ("vars" :: map sexp_binding (fn_vars f)))
        :: ("  " ++ sexp_list ("temps" :: map sexp_binding (fn_temps f)))
        :: "  (body"
        :: sexp_stmt_lines false "    " "))" (fn_body f) k
  end.

(** A struct definition in the dump. *)
Definition sexp_struct (co : composite_definition) : string :=
  sexp_list ("struct" :: co_name co :: map sexp_binding (co_members co)).

(** The lines of the dump of [p]. *)
Definition print_sexp_lines (externs : list ident) (p : program) : list string :=
  "(program"
    :: sexp_list ("externs" :: externs)
    :: sexp_list ["main"; prog_main p]
    :: map sexp_struct (prog_types p)
    ++ fold_right sexp_def_lines [")"] (prog_defs p).

(** The S-expression dump of [p] (grammar in the header). *)
Definition print_sexp (externs : list ident) (p : program) : string :=
  dump_lines (print_sexp_lines externs p).
