(** * Block-diagram controllers: syntax, rules and semantics *)

(** A controller written as a block diagram in the node model
    ([controller.blocks], DESIGN.md section 4), in the style of the
    Simulink blocks control laws are made of.  This file says what such
    a diagram *means*: a stream function, from a state and the inputs of
    one step to the next state and the outputs ([dg_step]), started from
    [dg_init].  [Diagramgen] turns a diagram into Embedded-Coder-shaped C
    ([Controller_initialize], [Controller_step] over [Controller_U],
    [Controller_Y] and a state global [Controller_DW]) and
    [Diagramproof] proves that this C computes [dg_step].

    ** Shape

    A diagram has the controller's interface (its inputs and outputs, as
    in the node model), a list of *states* (UnitDelay and discrete
    integrator blocks: the only blocks with memory), a list of
    *equations* in evaluation order, each defining one signal by one
    block, and for each output field the signal it takes.  An equation
    may only use signals defined before it (so the order given is an
    evaluation order, and a diagram has no algebraic loop: the front end
    sorts the blocks and names a loop that no delay breaks); the output
    of a state block is the signal of a [Bstate] equation, and its input
    may be any signal, since states are updated after every equation.

    ** Types

    A signal has a ROS primitive type among [bool], [int32], [uint32],
    [int64], [uint64], [float32], [float64] ([sig_prim]).  Every block
    but the relational and logical ones has its inputs, parameters and
    output of one type; relational and logical blocks give a [bool]
    ([unsigned char] 0 or 1).  [bool] signals only go through the
    logical, switch, delay and port blocks.

    ** Meaning of the blocks (for a step with state [s] and inputs [u])

    - [Binport x]: the input field [x]; [Bstate x]: the value of state
      [x] at the start of the step; [Bconst c]: [c].
    - [Bgain k a]: [a * k]; [Bsum [(p1, a1); ...]]: [±a1 ± a2 ...] left
      to right, a leading [-] being a negation; [Bproduct a b]: [a * b];
      [Bdivide a b]: [a / b] (floats only); [Babs a]: the sign bit
      cleared (floats only).  Floats: IEEE 754, round to nearest even
      ([Operators]).  Integers: two's complement wrap-around (Simulink's
      arithmetic with "saturate on integer overflow" off), never C's
      undefined signed overflow.
    - [Bminmax false [a1; ...; an]]: [x := a1], then for each later
      [ai], [x := ai] when [ai < x]: the first smallest input (a NaN
      input is skipped, unless it comes first); [true]: the same with
      [>].
    - [Bsaturation lo hi a]: [hi] if [a > hi], else [lo] if [a < lo],
      else [a] (a NaN passes through).
    - [Brelational op a b]: [1] if [a op b] holds, else [0] (IEEE
      comparisons for floats: a NaN is unordered).
    - [Blogical op [a1; ...]]: AND, OR, NAND, NOR, XOR (odd number of
      true inputs) of the inputs' truth values (non-zero is true), NOT
      of one input; [1] or [0].
    - [Bswitch crit thr a c b]: [a] if the control input [c] passes
      the criterion ([c >= thr], [c > thr], [c != 0]), else [b].
    - A state [x] of kind [Kdelay] (UnitDelay) becomes its input's
      value; of kind [Kintegrator kt lim] (discrete integrator, forward
      Euler, [kt] = gain times sample time) it becomes [x + kt * a],
      clamped to [lim] as [Bsaturation] does.  Its output in a step is
      its value at the start of the step. *)

From Coq Require Import String List ZArith Bool.
From Flocq Require Import IEEE754.Binary.
From ROSGen Require Import Maps FloatOps Syntax Values Operators Memory NodeModel.
Import ListNotations.
Local Open Scope Z_scope.
Local Open Scope string_scope.

(** ** Syntax *)

(** The arithmetic of [Bgain], [Bsum], [Bproduct], [Bdivide]. *)
Inductive aop : Type := Aadd | Asub | Amul | Adiv.

(** Relational operators. *)
Inductive relop : Type := Req | Rne | Rlt | Rgt | Rle | Rge.

(** Logical operators. *)
Inductive logop : Type := Land | Lor | Lnand | Lnor | Lxor | Lnot.

(** The criterion of a switch on its control input [c]. *)
Inductive switch_crit : Type :=
  | Cge     (**r [c >= threshold] *)
  | Cgt     (**r [c > threshold] *)
  | Cne0.   (**r [c != 0] *)

Inductive dblock : Type :=
  | Binport (x : ident)
  | Bstate (x : ident)
  | Bconst (c : val)
  | Bgain (k : val) (a : ident)
  | Bsum (terms : list (bool * ident))     (**r [true]: [+], [false]: [-] *)
  | Bproduct (a b : ident)
  | Bdivide (a b : ident)
  | Babs (a : ident)
  | Bminmax (ismax : bool) (args : list ident)
  | Bsaturation (lo hi : val) (a : ident)
  | Brelational (op : relop) (qa : prim) (a b : ident)   (**r [qa]: the inputs' type *)
  | Blogical (op : logop) (args : list ident)
  | Bswitch (crit : switch_crit) (qc : prim) (thr : val) (a c b : ident).
      (**r [qc]: the type of the control input [c] *)

(** An equation: the signal [eq_sig] of type [eq_type] is the output of
    [eq_block]. *)
Record equation : Type := mkeq {
  eq_sig : ident;
  eq_type : prim;
  eq_block : dblock
}.

Inductive state_kind : Type :=
  | Kdelay
  | Kintegrator (kt : val) (lim : option (val * val)).

(** A state: its name (a member of the state struct), type, initial
    value, the signal that feeds it, and its kind. *)
Record state_decl : Type := mkstate {
  st_name : ident;
  st_type : prim;
  st_init : val;
  st_input : ident;
  st_kind : state_kind
}.

(** A diagram, with the controller's C interface (as in the node model):
    [dg_in_var] ([Controller_U]) of [struct dg_in_struct] with fields
    [dg_inputs], likewise for the outputs, and the state global
    [dg_state_var] ([Controller_DW]) of [struct dg_state_struct] with
    one member per state. *)
Record diagram : Type := mkdiagram {
  dg_ctrl : ident;
  dg_in_var : ident;
  dg_in_struct : ident;
  dg_inputs : list (ident * prim);
  dg_out_var : ident;
  dg_out_struct : ident;
  dg_outputs : list (ident * prim);
  dg_state_var : ident;
  dg_state_struct : ident;
  dg_states : list state_decl;
  dg_eqs : list equation;
  dg_outs : list (ident * ident)           (**r output field, signal *)
}.

(** ** Types *)

Definition sig_prim (q : prim) : bool :=
  match q with
  | Pbool | Pint32 | Puint32 | Pint64 | Puint64 | Pfloat32 | Pfloat64 => true
  | _ => false
  end.

Definition num_prim (q : prim) : bool := sig_prim q && negb (prim_eqb q Pbool).

Definition float_prim (q : prim) : bool :=
  match q with Pfloat32 | Pfloat64 => true | _ => false end.

(** A constant of type [q]. *)
Definition val_of_prim (v : val) (q : prim) : bool := val_has_typeb v (ctype_of_prim q).

(** ** Well-formedness *)

Section WF.

Variable d : diagram.

(** [ctx]: the signals defined so far, with their types.  The rules
    below look a signal's type up through a function [lk]: [sig_type ctx]
    for the specification ([eqs_ok], [dg_wf]), a trie for the check that
    the per-node files compute ([dg_check], logarithmic lookups). *)
Definition sig_type (ctx : list (ident * prim)) (x : ident) : option prim := find_assoc x ctx.

Definition has_type_l (lk : ident -> option prim) (x : ident) (q : prim) : bool :=
  match lk x with Some q' => prim_eqb q q' | None => false end.

Definition has_type (ctx : list (ident * prim)) (x : ident) (q : prim) : bool :=
  has_type_l (sig_type ctx) x q.

Definition state_type (x : ident) : option prim :=
  option_map st_type (find (fun st => String.eqb (st_name st) x) (dg_states d)).

(** The rule of each block, for an output of type [q]. *)
Definition block_ok (lk : ident -> option prim) (b : dblock) (q : prim) : bool :=
  sig_prim q &&
  match b with
  | Binport x => match find_assoc x (dg_inputs d) with Some q' => prim_eqb q q' | None => false end
  | Bstate x => match state_type x with Some q' => prim_eqb q q' | None => false end
  | Bconst c => val_of_prim c q
  | Bgain k a => num_prim q && val_of_prim k q && has_type_l lk a q
  | Bsum terms => num_prim q && negb (Nat.eqb (length terms) 0)
                  && forallb (fun t => has_type_l lk (snd t) q) terms
  | Bproduct a b => num_prim q && has_type_l lk a q && has_type_l lk b q
  | Bdivide a b => float_prim q && has_type_l lk a q && has_type_l lk b q
  | Babs a => float_prim q && has_type_l lk a q
  | Bminmax _ args => num_prim q && negb (Nat.eqb (length args) 0)
                      && forallb (fun a => has_type_l lk a q) args
  | Bsaturation lo hi a => num_prim q && val_of_prim lo q && val_of_prim hi q && has_type_l lk a q
  | Brelational _ qa a b =>
      prim_eqb q Pbool && num_prim qa && has_type_l lk a qa && has_type_l lk b qa
  | Blogical op args =>
      prim_eqb q Pbool && forallb (fun a => has_type_l lk a Pbool) args &&
      match op, args with
      | Lnot, [_] => true
      | Lnot, _ => false
      | _, _ :: _ :: _ => true
      | _, _ => false
      end
  | Bswitch crit qc thr a c b =>
      has_type_l lk a q && has_type_l lk b q && has_type_l lk c qc &&
      match crit with
      | Cne0 => sig_prim qc
      | _ => num_prim qc && val_of_prim thr qc
      end
  end.

(** The equations, in order: each block well typed in the signals
    before it, each signal new. *)
Fixpoint eqs_ok (ctx : list (ident * prim)) (eqs : list equation) : option (list (ident * prim)) :=
  match eqs with
  | [] => Some ctx
  | e :: es =>
      if block_ok (sig_type ctx) (eq_block e) (eq_type e) && negb (in_ident (eq_sig e) (map fst ctx))
      then eqs_ok ((eq_sig e, eq_type e) :: ctx) es
      else None
  end.

Definition state_ok (lk : ident -> option prim) (st : state_decl) : bool :=
  sig_prim (st_type st) && val_of_prim (st_init st) (st_type st)
  && has_type_l lk (st_input st) (st_type st)
  && match st_kind st with
     | Kdelay => true
     | Kintegrator kt lim =>
         float_prim (st_type st) && val_of_prim kt (st_type st)
         && match lim with
            | Some (lo, hi) => val_of_prim lo (st_type st) && val_of_prim hi (st_type st)
            | None => true
            end
     end.

(** Every output field takes exactly one signal, of its type. *)
Definition outs_ok (lk : ident -> option prim) : bool :=
  Nat.eqb (length (dg_outs d)) (length (dg_outputs d))
  && nodup_idents (map fst (dg_outs d))
  && forallb (fun fq => match find_assoc (fst fq) (dg_outs d) with
                        | Some x => has_type_l lk x (snd fq)
                        | None => false
                        end) (dg_outputs d).

(** The C names of the controller file: the signals' temporaries
    ([rtb_] + signal), the three globals and two functions, the struct
    members. *)
Definition temp_of (x : ident) : ident := "rtb_" ++ x.

(** What is checked once the equations are: the states and outputs
    (their signals looked up by [lk]), the distinctness of names (by
    [nodup]), the interface. *)
Definition wf_rest (lk : ident -> option prim) (nodup : list ident -> bool) : bool :=
  forallb (state_ok lk) (dg_states d) && outs_ok lk
  && nodup (map st_name (dg_states d))
  && nodup (map fst (dg_inputs d))
  && nodup (map fst (dg_outputs d))
  && nodup (app [dg_in_var d; dg_out_var d; dg_state_var d;
                 dg_ctrl d ++ "_initialize"; dg_ctrl d ++ "_step"]
                (map (fun e => temp_of (eq_sig e)) (dg_eqs d)))
  && nodup [dg_in_struct d; dg_out_struct d; dg_state_struct d]
  && forallb (fun iq => sig_prim (snd iq)) (dg_inputs d)
  && forallb (fun oq => sig_prim (snd oq)) (dg_outputs d)
  && negb (Nat.eqb (length (dg_outputs d)) 0)
  && negb (Nat.eqb (length (dg_inputs d)) 0).

Definition dg_wf : bool :=
  match eqs_ok [] (dg_eqs d) with
  | Some ctx => wf_rest (sig_type ctx) nodup_idents
  | None => false
  end.

(** ** The same rules, computed fast *)

(** [dg_check] decides what [dg_wf] says ([dg_check_wf]) with the
    signals' types in a trie ([Maps]) and the distinctness checks by
    [find_dup]: the per-node file computes it, and [coqchk] checks that
    computation again with the kernel's reduction, where [dg_wf]'s
    association lists and pairwise comparisons take time quadratic in the
    number of blocks (BENCHMARKS.md section 6). *)
Definition tlook (t : ptree prim) (x : ident) : option prim := tget (enc_string x) t.

Fixpoint eqs_check (t : ptree prim) (eqs : list equation) : option (ptree prim) :=
  match eqs with
  | [] => Some t
  | e :: es =>
      if block_ok (tlook t) (eq_block e) (eq_type e)
         && match tlook t (eq_sig e) with Some _ => false | None => true end
      then eqs_check (tset (enc_string (eq_sig e)) (eq_type e) t) es
      else None
  end.

Definition distinct (l : list ident) : bool :=
  match find_dup enc_string l with Some _ => false | None => true end.

Definition dg_check : bool :=
  match eqs_check PLeaf (dg_eqs d) with
  | Some t => wf_rest (tlook t) distinct
  | None => false
  end.

Lemma forallb_ext_eq:
  forall (A : Type) (f g : A -> bool) l, (forall a, f a = g a) -> forallb f l = forallb g l.
Proof. intros A f g l H; induction l as [|a l IH]; simpl; [reflexivity | rewrite H, IH; reflexivity]. Qed.

Lemma has_type_l_ext:
  forall lk1 lk2, (forall x, lk1 x = lk2 x) -> forall x q, has_type_l lk1 x q = has_type_l lk2 x q.
Proof. intros lk1 lk2 H x q; unfold has_type_l; rewrite H; reflexivity. Qed.

Lemma block_ok_ext:
  forall lk1 lk2, (forall x, lk1 x = lk2 x) -> forall b q, block_ok lk1 b q = block_ok lk2 b q.
Proof.
  intros lk1 lk2 H b q. assert (E := has_type_l_ext lk1 lk2 H).
  unfold block_ok. destruct b; rewrite ?E; try reflexivity;
    try (erewrite forallb_ext_eq; [reflexivity | intros; apply E]).
Qed.

Lemma state_ok_ext:
  forall lk1 lk2, (forall x, lk1 x = lk2 x) -> forall st, state_ok lk1 st = state_ok lk2 st.
Proof. intros lk1 lk2 H st; unfold state_ok; rewrite (has_type_l_ext lk1 lk2 H); reflexivity. Qed.

Lemma outs_ok_ext:
  forall lk1 lk2, (forall x, lk1 x = lk2 x) -> outs_ok lk1 = outs_ok lk2.
Proof.
  intros lk1 lk2 H; unfold outs_ok. f_equal. apply forallb_ext_eq. intros fq.
  destruct (find_assoc (fst fq) (dg_outs d)); [apply has_type_l_ext; auto | reflexivity].
Qed.

Lemma enc_string_inj: forall a b, enc_string a = enc_string b -> a = b.
Proof. apply prefix_free_inj, enc_string_prefix_free. Qed.

Lemma distinct_nodup: forall l, distinct l = nodup_idents l.
Proof.
  intros l. unfold distinct.
  destruct (find_dup enc_string l) eqn:F; destruct (nodup_idents l) eqn:N; auto.
  - apply nodup_idents_spec in N. apply (find_dup_None _ _ enc_string_inj) in N. congruence.
  - assert (F' : find_dup enc_string l = None) by exact F.
    apply (find_dup_None _ _ enc_string_inj) in F'. apply nodup_idents_spec in F'. congruence.
Qed.

Lemma find_assoc_in_ident:
  forall (ctx : list (ident * prim)) x,
  in_ident x (map fst ctx) = match find_assoc x ctx with Some _ => true | None => false end.
Proof.
  induction ctx as [|[y q] ctx IH]; intros x; simpl; auto.
  unfold in_ident in *. simpl. destruct (string_dec x y) as [->|N].
  - destruct (ident_eq y y); [reflexivity | congruence].
  - rewrite <- IH. destruct (ident_eq y x); [congruence | reflexivity].
Qed.

Lemma eqs_check_ok:
  forall eqs t ctx t', (forall x, tlook t x = sig_type ctx x) -> eqs_check t eqs = Some t' ->
  exists ctx', eqs_ok ctx eqs = Some ctx' /\ forall x, tlook t' x = sig_type ctx' x.
Proof.
  induction eqs as [|e es IH]; intros t ctx t' H C; simpl in C |- *.
  - inversion C; subst. eauto.
  - rewrite (block_ok_ext (tlook t) (sig_type ctx) H) in C.
    rewrite H in C. change (sig_type ctx (eq_sig e)) with (find_assoc (eq_sig e) ctx) in C.
    rewrite find_assoc_in_ident.
    destruct (block_ok (sig_type ctx) (eq_block e) (eq_type e)) eqn:B;
      destruct (find_assoc (eq_sig e) ctx) eqn:F; simpl in C |- *; try discriminate C.
    apply (IH (tset (enc_string (eq_sig e)) (eq_type e) t) ((eq_sig e, eq_type e) :: ctx) t'); auto.
    intros x. unfold tlook, sig_type. simpl. destruct (string_dec x (eq_sig e)) as [->|N].
    + apply tget_tset_same.
    + rewrite tget_tset_other; [apply H|]. intros E. apply enc_string_inj in E. congruence.
Qed.

Theorem dg_check_wf: dg_check = true -> dg_wf = true.
Proof.
  unfold dg_check, dg_wf. destruct (eqs_check PLeaf (dg_eqs d)) as [t|] eqn:C; [|discriminate].
  destruct (eqs_check_ok (dg_eqs d) PLeaf [] t (fun x => tget_leaf _ _) C) as [ctx [E H]].
  rewrite E. unfold wf_rest in *. rewrite (outs_ok_ext _ _ H), !distinct_nodup.
  rewrite (forallb_ext_eq _ _ _ _ (state_ok_ext _ _ H)). auto.
Qed.

End WF.

(** ** Semantics *)

(** Two's complement wrap-around of integer arithmetic, IEEE 754 for
    floats; [Vundef] for operands of another type (never in a
    well-formed diagram). *)
Definition zop (op : aop) (n1 n2 : Z) : Z :=
  match op with Aadd => n1 + n2 | Asub => n1 - n2 | Amul => n1 * n2 | Adiv => 0 end.

Definition fop64 (op : aop) : float64 -> float64 -> float64 :=
  match op with Aadd => add64 | Asub => sub64 | Amul => mul64 | Adiv => div64 end.
Definition fop32 (op : aop) : float32 -> float32 -> float32 :=
  match op with Aadd => add32 | Asub => sub32 | Amul => mul32 | Adiv => div32 end.

Definition arith (op : aop) (q : prim) (a b : val) : val :=
  match q, a, b with
  | Pint32, Vint n1, Vint n2 =>
      match op with Adiv => Vundef | _ => Vint (wrap_signed 32 (zop op n1 n2)) end
  | Puint32, Vint n1, Vint n2 =>
      match op with Adiv => Vundef | _ => Vint (wrap_unsigned 32 (zop op n1 n2)) end
  | Pint64, Vlong n1, Vlong n2 =>
      match op with Adiv => Vundef | _ => Vlong (wrap_signed 64 (zop op n1 n2)) end
  | Puint64, Vlong n1, Vlong n2 =>
      match op with Adiv => Vundef | _ => Vlong (wrap_unsigned 64 (zop op n1 n2)) end
  | Pfloat64, Vfloat x, Vfloat y => Vfloat (fop64 op x y)
  | Pfloat32, Vsingle x, Vsingle y => Vsingle (fop32 op x y)
  | _, _, _ => Vundef
  end.

(** [-a]. *)
Definition negate (q : prim) (a : val) : val :=
  match q, a with
  | Pint32, Vint n => Vint (wrap_signed 32 (- n))
  | Puint32, Vint n => Vint (wrap_unsigned 32 (- n))
  | Pint64, Vlong n => Vlong (wrap_signed 64 (- n))
  | Puint64, Vlong n => Vlong (wrap_unsigned 64 (- n))
  | Pfloat64, Vfloat x => Vfloat (fneg 53 1024 x)
  | Pfloat32, Vsingle x => Vsingle (fneg 24 128 x)
  | _, _ => Vundef
  end.

(** The comparison of C for a relational operator. *)
Definition cmp_op (op : relop) : binary_operation :=
  match op with Req => Oeq | Rne => One | Rlt => Olt | Rgt => Ogt | Rle => Ole | Rge => Oge end.

(** [a op b] on values of type [q]: [Operators.sem_binop]'s comparison. *)
Definition compare (op : relop) (q : prim) (a b : val) : bool :=
  match sem_binop (cmp_op op) (ctype_of_prim q) a b with
  | Some (Vint 1) => true
  | _ => false
  end.

(** The truth value of a signal: non-zero. *)
Definition truth (v : val) : bool :=
  match bool_val v with Some b => b | None => false end.

Definition of_bool (b : bool) : val := Vint (if b then 1 else 0).

(** The logical operators on truth values. *)
Definition logic (op : logop) (bs : list bool) : bool :=
  match op with
  | Land => forallb id bs
  | Lor => existsb id bs
  | Lnand => negb (forallb id bs)
  | Lnor => negb (existsb id bs)
  | Lxor => fold_left xorb bs false
  | Lnot => negb (forallb id bs)
  end.

(** [hi] if [a > hi], else [lo] if [a < lo], else [a]. *)
Definition saturate (q : prim) (lo hi a : val) : val :=
  if compare Rgt q a hi then hi else if compare Rlt q a lo then lo else a.

(** The zero of a type. *)
Definition zero_of_prim (q : prim) : val := zero_val (ctype_of_prim q).

(** A signal environment: the value of each signal defined so far
    (newest first). *)
Definition senv := list (ident * val).

Definition sig (env : senv) (x : ident) : val :=
  match find_assoc x env with Some v => v | None => Vundef end.

(** The field [f] of a struct value. *)
Definition field_val (mv : mval) (f : ident) : val :=
  match mval_get mv [Sfield f] with Some (MVscalar v) => v | _ => Vundef end.

Section STEP.

Variable d : diagram.

(** The output of block [b] of type [q] in a step with state [s],
    inputs [u] and the signals [env] computed so far. *)
Definition eval_block (s u : mval) (env : senv) (b : dblock) (q : prim) : val :=
  match b with
  | Binport x => field_val u x
  | Bstate x => field_val s x
  | Bconst c => c
  | Bgain k a => arith Amul q (sig env a) k
  | Bsum [] => Vundef
  | Bsum ((p, a) :: terms) =>
      fold_left (fun (acc : val) (t : bool * ident) => arith (if fst t then Aadd else Asub) q acc (sig env (snd t)))
                terms (if p then sig env a else negate q (sig env a))
  | Bproduct a b => arith Amul q (sig env a) (sig env b)
  | Bdivide a b => arith Adiv q (sig env a) (sig env b)
  | Babs a =>
      match q, sig env a with
      | Pfloat64, Vfloat x => Vfloat (fabs 53 1024 x)
      | Pfloat32, Vsingle x => Vsingle (fabs 24 128 x)
      | _, _ => Vundef
      end
  | Bminmax _ [] => Vundef
  | Bminmax ismax (a :: args) =>
      fold_left (fun (x : val) (b : ident) => if compare (if ismax then Rgt else Rlt) q (sig env b) x
                            then sig env b else x) args (sig env a)
  | Bsaturation lo hi a => saturate q lo hi (sig env a)
  | Brelational op qa a b => of_bool (compare op qa (sig env a) (sig env b))
  | Blogical op args => of_bool (logic op (map (fun a => truth (sig env a)) args))
  | Bswitch crit qc thr a c b =>
      let vc := sig env c in
      let pass := match crit with
                  | Cge => compare Rge qc vc thr
                  | Cgt => compare Rgt qc vc thr
                  | Cne0 => truth vc
                  end in
      if pass then sig env a else sig env b
  end.

(** The signals of a step: the equations evaluated in order. *)
Fixpoint eval_eqs (s u : mval) (env : senv) (eqs : list equation) : senv :=
  match eqs with
  | [] => env
  | e :: es => eval_eqs s u ((eq_sig e, eval_block s u env (eq_block e) (eq_type e)) :: env) es
  end.

Definition step_signals (s u : mval) : senv := eval_eqs s u [] (dg_eqs d).

(** The output struct: each output field holds its signal. *)
Definition output_value (env : senv) : mval :=
  MVstruct (map (fun fq => (fst fq, MVscalar (match find_assoc (fst fq) (dg_outs d) with
                                               | Some x => sig env x
                                               | None => Vundef
                                               end))) (dg_outputs d)).

(** The next value of a state. *)
Definition next_state (s : mval) (env : senv) (st : state_decl) : val :=
  match st_kind st with
  | Kdelay => sig env (st_input st)
  | Kintegrator kt lim =>
      let x := arith Aadd (st_type st) (field_val s (st_name st))
                     (arith Amul (st_type st) kt (sig env (st_input st))) in
      match lim with
      | Some (lo, hi) => saturate (st_type st) lo hi x
      | None => x
      end
  end.

(** The state struct: one member per state. *)
Definition state_value (f : state_decl -> val) : mval :=
  MVstruct (map (fun st => (st_name st, MVscalar (f st))) (dg_states d)).

(** The initial state, and one step: from state [s] and inputs [u], the
    next state and the outputs. *)
Definition dg_init : mval := state_value st_init.

Definition dg_step (s u : mval) : mval * mval :=
  let env := step_signals s u in
  (state_value (next_state s env), output_value env).

End STEP.
