(** * Abstract syntax of the Clight subset emitted by pyrosgen *)

(** This is the project's own model of the C that the generator emits.  The
    constructor names follow CompCert's Clight ([Evar], [Etempvar], [Efield],
    [Ederef], [Eaddrof], [Sassign], [Sset], [Scall], [Ssequence], [Sloop],
    [Sreturn], [Tstruct], [tptr], ...) so that a port onto the real CompCert and
    VST is a renaming job.  Every definition is written for this project.

    Differences from CompCert's Clight, all deliberate simplifications for
    the code we emit:
    - identifiers are [string]s (the C names themselves), not [positive]s;
    - types carry no attributes, and 64-bit integers are [Tlong];
    - [Sloop] has a single body ([for (;;) s]); [while (c) s] is
      [Sloop (Ssequence (Sifthenelse c Sskip Sbreak) s)];
    - array indexing is a primitive [Eindex] rather than pointer arithmetic;
    - external functions are tagged with their meaning (the ROS C API and the
      controller interface), which the environment model of [Semantics]
      interprets. *)

From Coq Require Import String List ZArith Bool.
From Flocq Require Import IEEE754.Binary.
Import ListNotations.

(** ** Identifiers and floats *)

Definition ident := string.

(** IEEE 754 binary64 ([double]) and binary32 ([float]) numbers, from Flocq. *)
Definition float64 := binary_float 53 1024.
Definition float32 := binary_float 24 128.

(** ** Types *)

Inductive signedness : Type := Signed | Unsigned.

Inductive intsize : Type :=
  | I8    (**r [char] *)
  | I16   (**r [short] *)
  | I32.  (**r [int] *)

Inductive floatsize : Type :=
  | F32   (**r [float] *)
  | F64.  (**r [double] *)

Inductive type : Type :=
  | Tvoid                                  (**r [void] *)
  | Tint (sz : intsize) (sg : signedness)  (**r 8, 16, 32-bit integers *)
  | Tlong (sg : signedness)                (**r 64-bit integers ([long long]) *)
  | Tfloat (fs : floatsize)                (**r [float], [double] *)
  | Tpointer (t : type)                    (**r pointer to [t] *)
  | Tarray (t : type) (n : Z)              (**r fixed-size array [t[n]] *)
  | Tfunction (args : list type) (res : type)  (**r function type *)
  | Tstruct (id : ident).                  (**r [struct id] *)

Definition tptr (t : type) : type := Tpointer t.

(** Common abbreviations. *)
Definition tint : type := Tint I32 Signed.
Definition tuint : type := Tint I32 Unsigned.
Definition tuchar : type := Tint I8 Unsigned.
Definition tschar : type := Tint I8 Signed.
Definition tdouble : type := Tfloat F64.
Definition tfloat : type := Tfloat F32.

(** Decidable equality of types (the paper's [type_equal]). *)
Definition signedness_eq (a b : signedness) : {a = b} + {a <> b}.
Proof. decide equality. Defined.
Definition intsize_eq (a b : intsize) : {a = b} + {a <> b}.
Proof. decide equality. Defined.
Definition floatsize_eq (a b : floatsize) : {a = b} + {a <> b}.
Proof. decide equality. Defined.

Fixpoint type_eq (a b : type) {struct a} : {a = b} + {a <> b}.
Proof.
  decide equality;
    first [ apply signedness_eq | apply intsize_eq | apply floatsize_eq
          | apply Z.eq_dec | apply string_dec | apply list_eq_dec; apply type_eq
          | idtac ].
Defined.

Definition type_eqb (a b : type) : bool := if type_eq a b then true else false.

Lemma type_eqb_true : forall a b, type_eqb a b = true <-> a = b.
Proof.
  intros a b; unfold type_eqb; destruct (type_eq a b); split; congruence.
Qed.

(** ** Operators *)

(** The arithmetic of the subset (CompCert's names).  The typing rules
    ([Typing]) only allow operands that C's integer promotions and usual
    arithmetic conversions leave unchanged: both operands of a binary
    operator have the same type, [int], [unsigned int], [long long],
    [unsigned long long], [float] or [double].  So the printed C
    computes in exactly the type the AST says, and the semantics
    ([Values.sem_binop]) needs no implicit conversion. *)
Inductive unary_operation : Type :=
  | Oneg         (**r [-e] *)
  | Onotbool     (**r [!e]: 1 if [e] is zero, else 0, of type [int] *)
  | Oabsfloat.   (**r [fabs(e)]: the sign bit cleared (printed as a helper) *)

Inductive binary_operation : Type :=
  | Oadd | Osub | Omul | Odiv     (**r [+ - * /] *)
  | Omod                          (**r [%] (integers) *)
  | Oand | Oor | Oxor             (**r [& | ^] (integers) *)
  | Oeq | One | Olt | Ogt | Ole | Oge.  (**r [== != < > <= >=], of type [int] *)

Definition unary_operation_eq (a b : unary_operation) : {a = b} + {a <> b}.
Proof. decide equality. Defined.
Definition binary_operation_eq (a b : binary_operation) : {a = b} + {a <> b}.
Proof. decide equality. Defined.

(** ** Expressions *)

(** Every expression carries its type, as in Clight.  Integer constants are
    mathematical integers; the semantics normalises them to their type. *)
Inductive expr : Type :=
  | Econst_int (n : Z) (ty : type)          (**r integer constant (8/16/32 bits) *)
  | Econst_long (n : Z) (ty : type)         (**r 64-bit integer constant *)
  | Econst_float (f : float64) (ty : type)  (**r [double] constant *)
  | Econst_single (f : float32) (ty : type) (**r [float] constant *)
  | Evar (x : ident) (ty : type)            (**r global or addressable local variable *)
  | Etempvar (x : ident) (ty : type)        (**r temporary (non-addressable) variable *)
  | Ederef (e : expr) (ty : type)           (**r [*e] *)
  | Eaddrof (e : expr) (ty : type)          (**r [&e] *)
  | Efield (e : expr) (f : ident) (ty : type)  (**r [e.f] (use [Ederef] for [e->f]) *)
  | Eindex (e : expr) (i : expr) (ty : type)   (**r [e[i]], [e] of array type *)
  | Ecast (e : expr) (ty : type)            (**r [(ty) e] *)
  | Eunop (op : unary_operation) (e : expr) (ty : type)     (**r [op e] *)
  | Ebinop (op : binary_operation) (e1 e2 : expr) (ty : type).  (**r [e1 op e2] *)

Definition typeof (e : expr) : type :=
  match e with
  | Econst_int _ ty | Econst_long _ ty | Econst_float _ ty | Econst_single _ ty
  | Evar _ ty | Etempvar _ ty | Ederef _ ty | Eaddrof _ ty
  | Efield _ _ ty | Eindex _ _ ty | Ecast _ ty | Eunop _ _ ty | Ebinop _ _ _ ty => ty
  end.

(** ** Statements *)

Inductive statement : Type :=
  | Sskip                                        (**r do nothing *)
  | Sassign (lhs rhs : expr)                     (**r [lhs = rhs] (scalar or struct copy) *)
  | Sset (x : ident) (e : expr)                  (**r [tmp = e] *)
  | Scall (res : option ident) (f : expr) (args : list expr)  (**r function call *)
  | Ssequence (s1 s2 : statement)                (**r [s1; s2] *)
  | Sifthenelse (c : expr) (s1 s2 : statement)   (**r [if (c) s1 else s2] *)
  | Sloop (body : statement)                     (**r [for (;;) body] *)
  | Sbreak                                       (**r [break] *)
  | Sreturn (e : option expr).                   (**r [return e] *)

(** [while (c) s], as printed back by the printer. *)
Definition Swhile (c : expr) (s : statement) : statement :=
  Sloop (Ssequence (Sifthenelse c Sskip Sbreak) s).

(** ** Functions *)

Record function : Type := mkfunction {
  fn_return : type;
  fn_params : list (ident * type);
  fn_vars : list (ident * type);     (**r addressable local variables *)
  fn_temps : list (ident * type);    (**r temporaries *)
  fn_body : statement
}.

(** External functions are tagged with their meaning.  Topic names are the
    ROS graph names; the C name of the function is the identifier under which
    it is declared in the program. *)
Inductive external_function : Type :=
  | EF_ros_init                      (**r [void ros_init(void)] *)
  | EF_ros_ok                        (**r [int ros_ok(void)] *)
  | EF_ros_spinOnce                  (**r [void ros_spinOnce(void)]: runs callbacks *)
  | EF_ros_now                       (**r [unsigned long long ros_now(void)]: ROS time, ns *)
  | EF_ros_time_sec                  (**r [unsigned int ros_time_sec(void)]: its seconds *)
  | EF_ros_time_nsec                 (**r [unsigned int ros_time_nsec(void)]: its nanoseconds *)
  | EF_ros_rate_sleep (period_ms : Z)
      (**r [void ros_rate_sleep(void)]: sleeps until the end of the cycle
           of [period_ms] milliseconds (the period is part of the
           declaration's meaning, like the topic of [ros_subscribe_T]) *)
  | EF_ros_subscribe (topic : string) (msgty : ident) (queue : nat)
      (**r [void ros_subscribe_T(void ( *cb)(struct M * ))] *)
  | EF_ros_advertise (topic : string) (msgty : ident) (queue : nat)
      (**r [void ros_advertise_T(void)] *)
  | EF_ros_publish (topic : string) (msgty : ident)
      (**r [void ros_publish_T(struct M * msg)] *)
  | EF_controller_initialize (inputs outputs : ident)
      (**r [void Controller_initialize(void)]; [inputs]/[outputs] name the
           globals [Controller_U]/[Controller_Y] *)
  | EF_controller_step (inputs outputs : ident).
      (**r [void Controller_step(void)]: reads the global [inputs], writes
           only the global [outputs] and the controller's own state *)

Inductive fundef : Type :=
  | Internal (f : function)
  | External (ef : external_function) (params : list type) (res : type).

(** ** Programs *)

(** Struct definitions: members in declaration (= C layout) order. *)
Record composite_definition : Type := Composite {
  co_name : ident;
  co_members : list (ident * type)
}.

(** Global definitions.  Global variables have C static storage duration and
    are therefore zero-initialised. *)
Inductive globdef : Type :=
  | Gfun (fd : fundef)
  | Gvar (ty : type).

Record program : Type := mkprogram {
  prog_types : list composite_definition;
  prog_defs : list (ident * globdef);
  prog_main : ident
}.

(** ** Lookups *)

Fixpoint find_assoc {A : Type} (x : ident) (l : list (ident * A)) : option A :=
  match l with
  | [] => None
  | (y, a) :: l' => if string_dec x y then Some a else find_assoc x l'
  end.

Definition find_composite (id : ident) (l : list composite_definition)
  : option composite_definition :=
  find (fun co => if string_dec (co_name co) id then true else false) l.

Definition find_def (p : program) (id : ident) : option globdef :=
  find_assoc id (prog_defs p).

Definition type_of_function (f : function) : type :=
  Tfunction (map snd (fn_params f)) (fn_return f).

Definition type_of_fundef (fd : fundef) : type :=
  match fd with
  | Internal f => type_of_function f
  | External _ params res => Tfunction params res
  end.
