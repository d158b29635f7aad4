(** * From a block diagram to Embedded-Coder-shaped C *)

(** [dg_program d] is the controller's C unit, in the shape Embedded
    Coder gives it, so that the glue, the wrapper and the layout check
    treat it like a controller brought by the user:
<<
    struct ExtU_Controller_T Controller_U;   struct ExtY_Controller_T Controller_Y;
    struct DW_Controller_T Controller_DW;    (only if the diagram has states)
    void Controller_initialize(void) { Controller_DW.x = <initial value>; ... }
    void Controller_step(void) {
      <one temporary rtb_<signal> per equation>
      rtb_a = Controller_U.In1;  ...      the equations, in order
      Controller_Y.Out1 = rtb_m;  ...     the outputs
      Controller_DW.x = rtb_u;  ...       the state updates
    }
>>
    Signed integer arithmetic is computed in the unsigned type of the
    same width and converted back ([(int)((unsigned int)a + (unsigned
    int)b)]): wrap-around, as the diagram's semantics says, and never
    C's undefined signed overflow.  MinMax, Saturation and Switch are
    [if] statements; a relational or logical block converts its [int]
    result to [unsigned char].  [Diagramproof] proves that
    [Controller_step] computes [Diagram.dg_step]. *)

From Coq Require Import String List ZArith Bool.
From ROSGen Require Import Syntax Values Operators NodeModel Diagram.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope Z_scope.

(** ** Expressions *)

Definition ct (q : prim) : type := ctype_of_prim q.

(** The temporary of signal [x] of type [q]. *)
Definition tmp (x : ident) (q : prim) : expr := Etempvar (temp_of x) (ct q).

(** A constant.  A [bool] constant is an [int] constant converted to
    [unsigned char]: C has no literal of that type, and the conversion
    is what the printed C ([(unsigned char)1]) does. *)
Definition const_expr (v : val) (q : prim) : expr :=
  match v with
  | Vint n => match q with
              | Pbool => Ecast (Econst_int n tint) (ct q)
              | _ => Econst_int n (ct q)
              end
  | Vlong n => Econst_long n (ct q)
  | Vfloat f => Econst_float f (ct q)
  | Vsingle f => Econst_single f (ct q)
  | _ => Econst_int 0 (ct q)
  end.

Definition binop_of_aop (op : aop) : binary_operation :=
  match op with Aadd => Oadd | Asub => Osub | Amul => Omul | Adiv => Odiv end.

(** The unsigned type of the same width as a signed type. *)
Definition unsigned_of (q : prim) : option type :=
  match q with
  | Pint32 => Some tuint
  | Pint64 => Some (Tlong Unsigned)
  | _ => None
  end.

(** [a op b] on type [q], wrapping around for signed integers. *)
Definition arith_expr (op : aop) (q : prim) (a b : expr) : expr :=
  match unsigned_of q with
  | Some ut => Ecast (Ebinop (binop_of_aop op) (Ecast a ut) (Ecast b ut) ut) (ct q)
  | None => Ebinop (binop_of_aop op) a b (ct q)
  end.

(** [-a], likewise. *)
Definition neg_expr (q : prim) (a : expr) : expr :=
  match unsigned_of q with
  | Some ut => Ecast (Eunop Oneg (Ecast a ut) ut) (ct q)
  | None => Eunop Oneg a (ct q)
  end.

(** [a op b] as an [int] 0 or 1. *)
Definition cmp_expr (op : relop) (q : prim) (a b : expr) : expr :=
  Ebinop (cmp_op op) a b tint.

(** The truth value of a [bool] signal as an [int] 0 or 1: [(int)a != 0]. *)
Definition truth_expr (a : expr) : expr := Ebinop One (Ecast a tint) (Econst_int 0 tint) tint.

(** A logical operation on the truth values [ts] (at least one). *)
Definition logic_expr (op : logop) (ts : list expr) : expr :=
  let fold (bop : binary_operation) :=
      match ts with
      | [] => Econst_int 0 tint
      | t :: ts' => fold_left (fun (acc : expr) (t' : expr) => Ebinop bop acc t' tint) ts' t
      end in
  match op with
  | Land => fold Oand
  | Lor => fold Oor
  | Lxor => fold Oxor
  | Lnand => Eunop Onotbool (fold Oand) tint
  | Lnor => Eunop Onotbool (fold Oor) tint
  | Lnot => Eunop Onotbool (fold Oand) tint
  end.

(** The control condition of a switch, as an [int]. *)
Definition switch_cond (crit : switch_crit) (qc : prim) (thr : val) (c : expr) : expr :=
  match crit with
  | Cge => cmp_expr Rge qc c (const_expr thr qc)
  | Cgt => cmp_expr Rgt qc c (const_expr thr qc)
  | Cne0 =>
      if prim_eqb qc Pbool then truth_expr c
      else Ebinop One c (const_expr (zero_of_prim qc) qc) tint
  end.

(** ** Statements *)

(** The statement of an equation: it sets the signal's temporary. *)
Definition eq_stmt (d : diagram) (e : equation) : statement :=
  let x := temp_of (eq_sig e) in
  let q := eq_type e in
  let set (a : expr) := Sset x a in
  let this := Etempvar x (ct q) in
  match eq_block e with
  | Binport f => set (Efield (Evar (dg_in_var d) (Tstruct (dg_in_struct d))) f (ct q))
  | Bstate f => set (Efield (Evar (dg_state_var d) (Tstruct (dg_state_struct d))) f (ct q))
  | Bconst c => set (const_expr c q)
  | Bgain k a => set (arith_expr Amul q (tmp a q) (const_expr k q))
  | Bsum [] => Sskip
  | Bsum ((p, a) :: terms) =>
      set (fold_left (fun (acc : expr) (t : bool * ident) => arith_expr (if fst t then Aadd else Asub) q acc (tmp (snd t) q))
                     terms (if p then tmp a q else neg_expr q (tmp a q)))
  | Bproduct a b => set (arith_expr Amul q (tmp a q) (tmp b q))
  | Bdivide a b => set (arith_expr Adiv q (tmp a q) (tmp b q))
  | Babs a => set (Eunop Oabsfloat (tmp a q) (ct q))
  | Bminmax _ [] => Sskip
  | Bminmax ismax (a :: args) =>
      Ssequence (set (tmp a q))
        (fold_right (fun (b : ident) (k : statement) => Ssequence
                       (Sifthenelse (cmp_expr (if ismax then Rgt else Rlt) q (tmp b q) this)
                                    (set (tmp b q)) Sskip) k) Sskip args)
  | Bsaturation lo hi a =>
      Ssequence (set (tmp a q))
        (Sifthenelse (cmp_expr Rgt q this (const_expr hi q)) (set (const_expr hi q))
           (Sifthenelse (cmp_expr Rlt q this (const_expr lo q)) (set (const_expr lo q)) Sskip))
  | Brelational op qa a b => set (Ecast (cmp_expr op qa (tmp a qa) (tmp b qa)) (ct Pbool))
  | Blogical op args =>
      set (Ecast (logic_expr op (map (fun a => truth_expr (tmp a Pbool)) args)) (ct Pbool))
  | Bswitch crit qc thr a c b =>
      Sifthenelse (switch_cond crit qc thr (tmp c qc)) (set (tmp a q)) (set (tmp b q))
  end.

(** [Controller_Y.f = rtb_x;] for an output field [f] of type [q]. *)
Definition out_stmt (d : diagram) (fq : ident * prim) : statement :=
  let (f, q) := fq in
  match find_assoc f (dg_outs d) with
  | Some x => Sassign (Efield (Evar (dg_out_var d) (Tstruct (dg_out_struct d))) f (ct q)) (tmp x q)
  | None => Sskip
  end.

(** The member of a state in [Controller_DW]. *)
Definition state_lv (d : diagram) (st : state_decl) : expr :=
  Efield (Evar (dg_state_var d) (Tstruct (dg_state_struct d))) (st_name st) (ct (st_type st)).

(** The update of a state. *)
Definition update_stmt (d : diagram) (st : state_decl) : statement :=
  let q := st_type st in
  let x := state_lv d st in
  match st_kind st with
  | Kdelay => Sassign x (tmp (st_input st) q)
  | Kintegrator kt lim =>
      Ssequence (Sassign x (arith_expr Aadd q x (arith_expr Amul q (const_expr kt q) (tmp (st_input st) q))))
        match lim with
        | Some (lo, hi) =>
            Sifthenelse (cmp_expr Rgt q x (const_expr hi q)) (Sassign x (const_expr hi q))
              (Sifthenelse (cmp_expr Rlt q x (const_expr lo q)) (Sassign x (const_expr lo q)) Sskip)
        | None => Sskip
        end
  end.

Definition seq_list (l : list statement) : statement := fold_right Ssequence Sskip l.

(** ** The functions and the program *)

Definition step_name (d : diagram) : ident := dg_ctrl d ++ "_step".
Definition init_name (d : diagram) : ident := dg_ctrl d ++ "_initialize".

Definition step_function (d : diagram) : function :=
  mkfunction Tvoid [] [] (map (fun e => (temp_of (eq_sig e), ct (eq_type e))) (dg_eqs d))
    (Ssequence (seq_list (map (eq_stmt d) (dg_eqs d)))
       (Ssequence (seq_list (map (out_stmt d) (dg_outputs d)))
                  (seq_list (map (update_stmt d) (dg_states d))))).

Definition init_function (d : diagram) : function :=
  mkfunction Tvoid [] [] []
    (seq_list (map (fun st => Sassign (state_lv d st) (const_expr (st_init st) (st_type st)))
                   (dg_states d))).

Definition fields_composite (id : ident) (fs : list (ident * prim)) : composite_definition :=
  Composite id (map (fun fq => (fst fq, ct (snd fq))) fs).

Definition state_composite (d : diagram) : composite_definition :=
  Composite (dg_state_struct d) (map (fun st => (st_name st, ct (st_type st))) (dg_states d)).

(** The state struct and global exist only when the diagram has states
    (C has no empty struct). *)
Definition has_states (d : diagram) : bool := negb (Nat.eqb (length (dg_states d)) 0).

Definition dg_program (d : diagram) : program :=
  mkprogram
    ([fields_composite (dg_in_struct d) (dg_inputs d);
      fields_composite (dg_out_struct d) (dg_outputs d)]
     ++ (if has_states d then [state_composite d] else []))
    ([(dg_in_var d, Gvar (Tstruct (dg_in_struct d)));
      (dg_out_var d, Gvar (Tstruct (dg_out_struct d)))]
     ++ (if has_states d then [(dg_state_var d, Gvar (Tstruct (dg_state_struct d)))] else [])
     ++ [(init_name d, Gfun (Internal (init_function d)));
         (step_name d, Gfun (Internal (step_function d)))])
    (step_name d).
