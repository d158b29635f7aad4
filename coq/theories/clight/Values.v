(** * Run-time values and structured memory values *)

(** The values manipulated by the semantics of the emitted Clight subset.

    - Scalars ([val]) are mathematical integers tagged with their width
      class ([Vint] for 8/16/32-bit types, [Vlong] for 64-bit ones), IEEE
      floats, pointers and function pointers.  An integer value is always
      kept as the mathematical value of the C object *in its type*: a
      [signed char] holding -1 is [Vint (-1)], an [unsigned char] holding
      255 is [Vint 255].  Normalisation to the type ([norm_int],
      [norm_long]) happens at every cast and every store, so wrap-around
      is exactly C's (two's complement for the signed conversions, as gcc
      defines them).
    - A pointer is a memory block together with a [path] into the
      structured value stored in that block: a list of field selections
      and array subscripts.  The emitted code never does pointer
      arithmetic, so this is all a pointer needs to say.
    - Memory does not hold bytes but structured values ([mval]): scalars,
      structs (fields in member order, with their names) and arrays.  The
      reasons why this abstraction is adequate for the emitted code are
      given in the header of [Memory]. *)

From Coq Require Import String List ZArith Bool Lia.
From Flocq Require Import IEEE754.Binary.
From ROSGen Require Import Syntax.
Import ListNotations.
Local Open Scope Z_scope.

(** ** Blocks and paths *)

(** Memory blocks are named by positive numbers, allocated in increasing
    order. *)
Definition block := positive.

(** One step into a structured value: select a struct field, or an array
    element. *)
Inductive step : Type :=
  | Sfield (f : ident)   (**r [.f] *)
  | Sindex (i : Z).      (**r [[i]] *)

(** A path from the start of a block to a sub-value. *)
Definition path := list step.

Definition ident_eq := string_dec.

Definition step_eq (a b : step) : {a = b} + {a <> b}.
Proof. decide equality; [apply string_dec | apply Z.eq_dec]. Defined.

Definition path_eq (a b : path) : {a = b} + {a <> b} := list_eq_dec step_eq a b.

(** ** Scalar values *)

Inductive val : Type :=
  | Vundef                        (**r an unspecified (uninitialised) value *)
  | Vint (n : Z)                  (**r a value of an 8, 16 or 32-bit integer type *)
  | Vlong (n : Z)                 (**r a value of a 64-bit integer type *)
  | Vsingle (f : float32)         (**r a [float] *)
  | Vfloat (f : float64)          (**r a [double] *)
  | Vptr (b : block) (p : path)   (**r a pointer to the sub-value at [p] in block [b] *)
  | Vfptr (id : ident).           (**r a pointer to the function named [id] *)

(** ** Integer wrap-around *)

(** Width in bits of the integer types. *)
Definition bitsize (sz : intsize) : Z :=
  match sz with I8 => 8 | I16 => 16 | I32 => 32 end.

(** Conversion of the mathematical integer [n] to an unsigned, resp.
    signed, integer type of [bits] bits (C11 6.3.1.3; for the signed case
    the implementation-defined result is gcc's: reduction modulo
    [2^bits] into the signed range). *)
Definition wrap_unsigned (bits n : Z) : Z := n mod 2 ^ bits.

Definition wrap_signed (bits n : Z) : Z :=
  let m := n mod 2 ^ bits in
  if m <? 2 ^ (bits - 1) then m else m - 2 ^ bits.

Definition wrap (bits : Z) (sg : signedness) (n : Z) : Z :=
  match sg with
  | Signed => wrap_signed bits n
  | Unsigned => wrap_unsigned bits n
  end.

(** Normalisation of an integer to the type [Tint sz sg], resp. [Tlong sg]. *)
Definition norm_int (sz : intsize) (sg : signedness) (n : Z) : Z := wrap (bitsize sz) sg n.
Definition norm_long (sg : signedness) (n : Z) : Z := wrap 64 sg n.

Lemma wrap_idem:
  forall bits sg n, 0 < bits -> wrap bits sg (wrap bits sg n) = wrap bits sg n.
Proof.
  intros bits sg n Hb. assert (Hpos: 0 < 2 ^ bits) by (apply Z.pow_pos_nonneg; lia).
  destruct sg; unfold wrap, wrap_signed, wrap_unsigned.
  - assert (Hhalf: 2 ^ bits = 2 * 2 ^ (bits - 1)).
    { replace bits with (Z.succ (bits - 1)) at 1 by lia. apply Z.pow_succ_r. lia. }
    set (m := n mod 2 ^ bits).
    assert (Hm: 0 <= m < 2 ^ bits) by (apply Z.mod_pos_bound; lia).
    destruct (m <? 2 ^ (bits - 1)) eqn:E.
    + rewrite Z.mod_small by lia. rewrite E. reflexivity.
    + replace ((m - 2 ^ bits) mod 2 ^ bits) with m.
      * rewrite E. reflexivity.
      * replace (m - 2 ^ bits) with (m + (-1) * 2 ^ bits) by lia.
        rewrite Z.mod_add by lia. rewrite Z.mod_small by lia. reflexivity.
  - apply Z.mod_mod. lia.
Qed.

Lemma norm_int_idem: forall sz sg n, norm_int sz sg (norm_int sz sg n) = norm_int sz sg n.
Proof. intros; unfold norm_int; apply wrap_idem; destruct sz; simpl; lia. Qed.

Lemma norm_long_idem: forall sg n, norm_long sg (norm_long sg n) = norm_long sg n.
Proof. intros; unfold norm_long; apply wrap_idem; lia. Qed.

(** ** Typing of scalar values *)

(** [val_has_type v ty]: [v] is a value of the scalar type [ty]; integers
    must be in the range of their type.  The null pointer is [Vint 0]. *)
Definition val_has_type (v : val) (ty : type) : Prop :=
  match ty, v with
  | Tint sz sg, Vint n => norm_int sz sg n = n
  | Tlong sg, Vlong n => norm_long sg n = n
  | Tfloat F64, Vfloat _ => True
  | Tfloat F32, Vsingle _ => True
  | Tpointer _, (Vptr _ _ | Vfptr _) => True
  | Tpointer _, Vint z => z = 0
  | _, _ => False
  end.

(** Its decision procedure. *)
Definition val_has_typeb (v : val) (ty : type) : bool :=
  match ty, v with
  | Tint sz sg, Vint n => Z.eqb (norm_int sz sg n) n
  | Tlong sg, Vlong n => Z.eqb (norm_long sg n) n
  | Tfloat F64, Vfloat _ => true
  | Tfloat F32, Vsingle _ => true
  | Tpointer _, (Vptr _ _ | Vfptr _) => true
  | Tpointer _, Vint z => Z.eqb z 0
  | _, _ => false
  end.

Lemma val_has_typeb_correct:
  forall v ty, val_has_typeb v ty = true <-> val_has_type v ty.
Proof.
  intros v ty; destruct ty as [| sz sg | sg | [|] | t | t len | args r | id ];
    destruct v; simpl; try (split; intros; first [discriminate | contradiction | exact I | reflexivity]);
    apply Z.eqb_eq.
Qed.

(** ** Casts *)

(** [sem_cast v ty] converts [v] to the type [ty], as an explicit cast or
    the implicit conversion of an assignment does.  Integer-to-integer
    conversions wrap around; pointers and floats convert only to their own
    kind (float conversions are never emitted).  [None] means the cast is
    undefined. *)
Definition sem_cast (v : val) (ty : type) : option val :=
  match ty, v with
  | Tint sz sg, (Vint n | Vlong n) => Some (Vint (norm_int sz sg n))
  | Tlong sg, (Vint n | Vlong n) => Some (Vlong (norm_long sg n))
  | Tfloat F64, Vfloat _ => Some v
  | Tfloat F32, Vsingle _ => Some v
  | Tpointer _, (Vptr _ _ | Vfptr _) => Some v
  | Tpointer _, Vint 0 => Some v
  | _, _ => None
  end.

Lemma sem_cast_has_type:
  forall v ty v', sem_cast v ty = Some v' -> val_has_type v' ty.
Proof.
  intros v ty v' H; destruct ty as [| sz sg | sg | [|] | t | t len | args r | id ];
    destruct v as [| n | n | f | f | b p | fid]; simpl in H; try discriminate;
    try (destruct n; [inversion H; subst; reflexivity | discriminate | discriminate]);
    inversion H; subst; simpl; auto using norm_int_idem, norm_long_idem.
Qed.

Lemma sem_cast_same:
  forall v ty, val_has_type v ty -> sem_cast v ty = Some v.
Proof.
  intros v ty H; destruct ty as [| sz sg | sg | [|] | t | t len | args r | id ];
    destruct v as [| n | n | f | f | b p | fid]; simpl in H |- *; try contradiction;
    try (rewrite H; reflexivity); auto.
Qed.

(** ** Truth values *)

(** The truth value of a scalar used as a condition ([if (v)]): non-zero
    integers, non-null pointers and non-zero floats are true. *)
Definition bool_val (v : val) : option bool :=
  match v with
  | Vint n | Vlong n => Some (negb (Z.eqb n 0))
  | Vptr _ _ | Vfptr _ => Some true
  | Vsingle (B754_zero _ _ _) | Vfloat (B754_zero _ _ _) => Some false
  | Vsingle _ | Vfloat _ => Some true
  | Vundef => None
  end.

(** ** Structured memory values *)

(** What a memory block holds: a scalar, a struct (its fields in member
    order, each with its name) or an array (its elements in order). *)
Inductive mval : Type :=
  | MVscalar (v : val)
  | MVstruct (fields : list (ident * mval))
  | MVarray (elems : list mval).

(** An induction principle that goes into fields and elements. *)
Section MVAL_IND.
Variable P : mval -> Prop.
Hypothesis Hscalar : forall v, P (MVscalar v).
Hypothesis Hstruct : forall fs, Forall (fun fv => P (snd fv)) fs -> P (MVstruct fs).
Hypothesis Harray : forall es, Forall P es -> P (MVarray es).

Fixpoint mval_ind2 (mv : mval) : P mv :=
  match mv as mv0 return P mv0 with
  | MVscalar v => Hscalar v
  | MVstruct fs =>
      Hstruct fs
        ((fix fields (l : list (ident * mval)) : Forall (fun fv => P (snd fv)) l :=
            match l with
            | [] => Forall_nil _
            | fv :: l' => Forall_cons fv (mval_ind2 (snd fv)) (fields l')
            end) fs)
  | MVarray es =>
      Harray es
        ((fix elems (l : list mval) : Forall P l :=
            match l with
            | [] => Forall_nil _
            | e :: l' => Forall_cons e (mval_ind2 e) (elems l')
            end) es)
  end.
End MVAL_IND.

(** ** Composite environments *)

(** The struct definitions of a program, in C declaration order. *)
Definition composite_env := list composite_definition.

(** The type of member [f] in a member list. *)
Definition field_type (f : ident) (members : list (ident * type)) : option type :=
  find_assoc f members.

(** The members of [struct id]. *)
Definition struct_members (ce : composite_env) (id : ident) : option (list (ident * type)) :=
  match find_composite id ce with
  | Some co => Some (co_members co)
  | None => None
  end.

(** Scalar types are those whose values live in a [val]. *)
Definition is_scalar_type (ty : type) : bool :=
  match ty with
  | Tint _ _ | Tlong _ | Tfloat _ | Tpointer _ => true
  | _ => false
  end.

(** ** Typing of memory values *)

(** [mval_has_type ce ty mv]: [mv] is a value of type [ty]: a well-typed
    scalar for a scalar type, all members in declaration order for a
    struct, exactly [n] elements for an array [t[n]]. *)
Inductive mval_has_type (ce : composite_env) : type -> mval -> Prop :=
  | mht_scalar : forall ty v,
      is_scalar_type ty = true -> val_has_type v ty ->
      mval_has_type ce ty (MVscalar v)
  | mht_struct : forall id members fs,
      struct_members ce id = Some members ->
      fields_have_type ce members fs ->
      mval_has_type ce (Tstruct id) (MVstruct fs)
  | mht_array : forall t n es,
      Z.of_nat (length es) = n ->
      elems_have_type ce t es ->
      mval_has_type ce (Tarray t n) (MVarray es)
with fields_have_type (ce : composite_env) : list (ident * type) -> list (ident * mval) -> Prop :=
  | fht_nil : fields_have_type ce [] []
  | fht_cons : forall f t mv members fs,
      mval_has_type ce t mv -> fields_have_type ce members fs ->
      fields_have_type ce ((f, t) :: members) ((f, mv) :: fs)
with elems_have_type (ce : composite_env) : type -> list mval -> Prop :=
  | eht_nil : forall t, elems_have_type ce t []
  | eht_cons : forall t mv es,
      mval_has_type ce t mv -> elems_have_type ce t es ->
      elems_have_type ce t (mv :: es).

(** The decision procedure, by recursion on the value. *)
Fixpoint mval_typecheck (ce : composite_env) (ty : type) (mv : mval) {struct mv} : bool :=
  match mv with
  | MVscalar v => is_scalar_type ty && val_has_typeb v ty
  | MVstruct fs =>
      match ty with
      | Tstruct id =>
          match struct_members ce id with
          | Some members =>
              (fix check_fields (ms : list (ident * type)) (l : list (ident * mval)) {struct l} : bool :=
                 match ms, l with
                 | [], [] => true
                 | (f, t) :: ms', (g, v) :: l' =>
                     (if ident_eq f g then true else false)
                     && mval_typecheck ce t v && check_fields ms' l'
                 | _, _ => false
                 end) members fs
          | None => false
          end
      | _ => false
      end
  | MVarray es =>
      match ty with
      | Tarray t n =>
          Z.eqb (Z.of_nat (length es)) n
          && (fix check_elems (l : list mval) : bool :=
                match l with
                | [] => true
                | v :: l' => mval_typecheck ce t v && check_elems l'
                end) es
      | _ => false
      end
  end.

Lemma mval_typecheck_correct:
  forall ce mv ty, mval_typecheck ce ty mv = true -> mval_has_type ce ty mv.
Proof.
  intros ce mv; induction mv as [v | fs IH | es IH] using mval_ind2; intros ty H; simpl in H.
  - apply andb_prop in H as [H1 H2]. constructor; auto. apply val_has_typeb_correct; auto.
  - destruct ty; try discriminate.
    destruct (struct_members ce id) as [members|] eqn:SM; try discriminate.
    econstructor; [exact SM|]. clear SM.
    revert members H; induction IH as [|[g v] fs' Hv IHfs IHrec]; intros members H;
      destruct members as [|[f t] ms]; try discriminate.
    + constructor.
    + apply andb_prop in H as [H H3]; apply andb_prop in H as [H1 H2].
      destruct (ident_eq f g); try discriminate; subst g.
      constructor; auto.
  - destruct ty; try discriminate.
    apply andb_prop in H as [H1 H2]. apply Z.eqb_eq in H1.
    constructor; auto. clear H1.
    induction IH as [|v es' Hv IHes IHrec]; constructor.
    + apply andb_prop in H2 as [H3 H4]; auto.
    + apply andb_prop in H2 as [H3 H4]; auto.
Qed.

Lemma mval_typecheck_complete:
  forall ce mv ty, mval_has_type ce ty mv -> mval_typecheck ce ty mv = true.
Proof.
  intros ce mv; induction mv as [v | fs IH | es IH] using mval_ind2; intros ty H;
    inversion H as [ty' v' Hs Hv | id members fs' SM Hf | t n es' Hn He]; subst; simpl.
  - rewrite Hs; apply val_has_typeb_correct; auto.
  - rewrite SM. clear SM H.
    revert members Hf; induction IH as [|[g v] fs' Hv IHfs IHrec]; intros members Hf;
      inversion Hf as [| f t mv ms fs'' Hmv Hms]; subst; simpl.
    + reflexivity.
    + destruct (ident_eq g g) as [_|C]; [|congruence]. simpl in Hv.
      rewrite (Hv _ Hmv). simpl. apply IHrec; auto.
  - rewrite Z.eqb_refl. simpl. clear H.
    induction IH as [|v es' Hv IHes IHrec]; inversion He as [| t' mv es'' Hmv Hes]; subst.
    + reflexivity.
    + rewrite (Hv _ Hmv). simpl. apply IHrec; auto.
Qed.

Lemma mval_typecheck_iff:
  forall ce ty mv, mval_typecheck ce ty mv = true <-> mval_has_type ce ty mv.
Proof.
  split; [apply mval_typecheck_correct | apply mval_typecheck_complete].
Qed.

(** ** Well-formed composite environments *)

(** Membership of an identifier in a list, as a boolean. *)
Definition in_ident (x : ident) (l : list ident) : bool :=
  existsb (fun y => if ident_eq y x then true else false) l.

Lemma in_ident_spec: forall x l, in_ident x l = true <-> In x l.
Proof.
  intros x l; unfold in_ident; rewrite existsb_exists; split.
  - intros [y [Hy E]]; destruct (ident_eq y x); [subst; auto | discriminate].
  - intros H; exists x; split; auto; destruct (ident_eq x x); congruence.
Qed.

(** No identifier occurs twice. *)
Fixpoint nodup_idents (l : list ident) : bool :=
  match l with
  | [] => true
  | x :: l' => negb (in_ident x l') && nodup_idents l'
  end.

Lemma nodup_idents_spec: forall l, nodup_idents l = true <-> NoDup l.
Proof.
  induction l as [|x l IH]; simpl.
  - split; auto using NoDup_nil.
  - rewrite andb_true_iff, IH, negb_true_iff. split.
    + intros [H1 H2]; constructor; auto. intros Hin; apply in_ident_spec in Hin; congruence.
    + intros H; inversion H as [|? ? Hn Hd]; subst; split; auto.
      destruct (in_ident x l) eqn:E; auto. apply in_ident_spec in E; contradiction.
Qed.

(** [complete_type known ty]: [ty] is the type of an object whose size is
    known when the structs named in [known] are defined (a scalar, an
    array of complete elements, a defined struct).  Pointer targets need
    not be complete. *)
Fixpoint complete_type (known : list ident) (ty : type) : bool :=
  match ty with
  | Tint _ _ | Tlong _ | Tfloat _ | Tpointer _ => true
  | Tarray t n => Z.leb 0 n && complete_type known t
  | Tstruct id => in_ident id known
  | Tvoid | Tfunction _ _ => false
  end.

(** The names of the structs of an environment. *)
Definition composite_names (ce : composite_env) : list ident := map co_name ce.

(** The struct definitions come in C order: each struct is defined once,
    its member names are distinct, and the types of its members are
    complete using the structs defined before it only (so there is no
    recursion through struct members, as C requires). *)
Fixpoint composites_ok (known : list ident) (ce : composite_env) : bool :=
  match ce with
  | [] => true
  | co :: ce' =>
      negb (in_ident (co_name co) known)
      && nodup_idents (map fst (co_members co))
      && forallb (fun m => complete_type known (snd m)) (co_members co)
      && composites_ok (co_name co :: known) ce'
  end.

Definition wf_composites (ce : composite_env) : Prop := composites_ok [] ce = true.

Lemma complete_type_incl:
  forall k1 k2 ty, (forall x, In x k1 -> In x k2) ->
  complete_type k1 ty = true -> complete_type k2 ty = true.
Proof.
  intros k1 k2 ty Hincl; induction ty; simpl; auto.
  - rewrite !andb_true_iff; intuition.
  - rewrite !in_ident_spec; auto.
Qed.

Lemma composites_ok_inv:
  forall ce known, composites_ok known ce = true ->
  NoDup (composite_names ce)
  /\ (forall x, In x (composite_names ce) -> ~ In x known)
  /\ (forall pre co post, ce = pre ++ co :: post ->
        NoDup (map fst (co_members co))
        /\ forall f t, In (f, t) (co_members co) ->
                       complete_type (composite_names pre ++ known) t = true).
Proof.
  induction ce as [|co ce IH]; intros known H; simpl in H.
  - split; [constructor|]. split; [simpl; tauto|].
    intros pre co post E; destruct pre; discriminate.
  - rewrite !andb_true_iff in H. destruct H as [[[H1 H2] H3] H4].
    apply negb_true_iff in H1.
    destruct (IH _ H4) as [IH1 [IH2 IH3]].
    split; [|split].
    + simpl; constructor; auto. intros Hin; apply (IH2 _ Hin); simpl; auto.
    + intros x [Hx|Hx] Hk.
      * subst; apply in_ident_spec in Hk; congruence.
      * apply (IH2 x Hx); simpl; auto.
    + intros pre co' post E. destruct pre as [|c pre]; simpl in E; inversion E; subst.
      * split; [apply nodup_idents_spec; auto|].
        intros f t Hin. rewrite forallb_forall in H3. apply (H3 _ Hin).
      * destruct (IH3 pre co' post eq_refl) as [A B]. split; auto.
        intros f t Hin. eapply complete_type_incl; [|apply (B f t Hin)].
        intros x; rewrite !in_app_iff; simpl; tauto.
Qed.

Lemma NoDup_app_disjoint:
  forall (A : Type) (l1 l2 : list A) x, NoDup (l1 ++ l2) -> In x l1 -> ~ In x l2.
Proof.
  induction l1 as [|y l1 IH]; simpl; intros l2 x ND Hx; [contradiction|].
  inversion ND as [|? ? Hy ND']; subst. destruct Hx as [Hx|Hx]; [subst|eauto].
  intros Hin; apply Hy, in_app_iff; auto.
Qed.

Lemma find_composite_split:
  forall id ce co, find_composite id ce = Some co ->
  co_name co = id /\ exists pre post, ce = pre ++ co :: post /\ ~ In id (composite_names pre).
Proof.
  unfold find_composite; induction ce as [|c ce IH]; simpl; intros co H; try discriminate.
  destruct (string_dec (co_name c) id) as [E|N].
  - inversion H; subst. split; auto. exists [], ce; simpl; auto.
  - destruct (IH _ H) as [A [pre [post [B C]]]]. split; auto.
    exists (c :: pre), post; simpl; split; [congruence|]. intros [D|D]; auto.
Qed.

(** ** Default values of a type *)

(** The value of an object of type [ty] whose scalars are all
    [dflt ty'] ([ty'] the scalar's type): [zs id] gives the value of
    [struct id]. *)
Fixpoint default_of (dflt : type -> val) (zs : ident -> mval) (ty : type) : mval :=
  match ty with
  | Tarray t n => MVarray (repeat (default_of dflt zs t) (Z.to_nat n))
  | Tstruct id => zs id
  | _ => MVscalar (dflt ty)
  end.

(** The default value of [struct id] in a composite environment given in
    *reverse* C order (each struct uses only the ones after it).  The
    recursion is on that list, which is why struct members cannot be of
    the struct's own type. *)
Fixpoint struct_default (dflt : type -> val) (rce : composite_env) (id : ident) : mval :=
  match rce with
  | [] => MVstruct []
  | co :: rce' =>
      if ident_eq (co_name co) id
      then MVstruct (map (fun m => (fst m, default_of dflt (struct_default dflt rce') (snd m)))
                         (co_members co))
      else struct_default dflt rce' id
  end.

Definition default_mval (dflt : type -> val) (ce : composite_env) (ty : type) : mval :=
  default_of dflt (struct_default dflt (rev ce)) ty.

(** C's static zero-initialisation: integers 0, floats +0.0, null
    pointers. *)
Definition zero_val (ty : type) : val :=
  match ty with
  | Tint _ _ => Vint 0
  | Tlong _ => Vlong 0
  | Tfloat F64 => Vfloat (B754_zero 53 1024 false)
  | Tfloat F32 => Vsingle (B754_zero 24 128 false)
  | Tpointer _ => Vint 0
  | _ => Vundef
  end.

(** The initial value of a global variable of type [ty]. *)
Definition zero_mval (ce : composite_env) (ty : type) : mval := default_mval zero_val ce ty.

(** The initial value of a local variable: the right shape, every scalar
    unspecified. *)
Definition undef_mval (ce : composite_env) (ty : type) : mval := default_mval (fun _ => Vundef) ce ty.

Lemma default_of_ext:
  forall dflt zs1 zs2 known ty,
  (forall id, In id known -> zs1 id = zs2 id) ->
  complete_type known ty = true ->
  default_of dflt zs1 ty = default_of dflt zs2 ty.
Proof.
  intros dflt zs1 zs2 known ty Hzs; induction ty; simpl; intros H; auto.
  - apply andb_prop in H as [_ H]. rewrite IHty; auto.
  - apply Hzs, in_ident_spec; auto.
Qed.

Lemma struct_default_app:
  forall dflt l1 l2 id, ~ In id (composite_names l1) ->
  struct_default dflt (l1 ++ l2) id = struct_default dflt l2 id.
Proof.
  induction l1 as [|co l1 IH]; simpl; intros l2 id H; auto.
  destruct (ident_eq (co_name co) id); [tauto|]. apply IH; tauto.
Qed.

Lemma composite_names_rev: forall l x, In x (composite_names (rev l)) <-> In x (composite_names l).
Proof.
  intros l x; unfold composite_names; rewrite map_rev, <- in_rev; tauto.
Qed.

(** The default value of a struct is the struct of the default values of
    its members. *)
Lemma default_mval_struct:
  forall dflt ce id members,
  wf_composites ce ->
  struct_members ce id = Some members ->
  default_mval dflt ce (Tstruct id)
  = MVstruct (map (fun m => (fst m, default_mval dflt ce (snd m))) members).
Proof.
  intros dflt ce id members WF SM. unfold struct_members in SM.
  destruct (find_composite id ce) as [co|] eqn:FC; try discriminate. inversion SM; subst members.
  destruct (find_composite_split _ _ _ FC) as [Hname [pre [post [E Hpre]]]].
  destruct (composites_ok_inv ce [] WF) as [ND [_ MEM]].
  destruct (MEM pre co post E) as [_ Hcompl].
  assert (NDs: NoDup (composite_names pre ++ co_name co :: composite_names post)).
  { rewrite E in ND; unfold composite_names in *; rewrite map_app in ND; exact ND. }
  assert (Hpost: forall x, In x (composite_names pre) \/ x = co_name co -> ~ In x (composite_names post)).
  { intros x Hx Hin. destruct Hx as [Hx|Hx].
    - apply (NoDup_app_disjoint _ _ _ _ NDs Hx). simpl; auto.
    - subst x. apply NoDup_remove_2 in NDs. apply NDs. rewrite in_app_iff; auto. }
  unfold default_mval; simpl. rewrite E, rev_app_distr. simpl.
  rewrite <- app_assoc. simpl.
  rewrite struct_default_app by (rewrite composite_names_rev; apply Hpost; auto).
  simpl. destruct (ident_eq (co_name co) id) as [_|C]; [|congruence].
  f_equal. apply map_ext_in. intros [f t] Hin. simpl. f_equal.
  apply default_of_ext with (known := composite_names pre ++ []).
  - intros x Hx. rewrite app_nil_r in Hx.
    rewrite struct_default_app by (rewrite composite_names_rev; apply Hpost; auto).
    simpl. destruct (ident_eq (co_name co) x) as [C|_]; auto.
    exfalso. subst x. apply NoDup_remove_2 in NDs. apply NDs. rewrite in_app_iff; auto.
  - apply (Hcompl f t Hin).
Qed.

Lemma zero_mval_struct:
  forall ce id members,
  wf_composites ce ->
  struct_members ce id = Some members ->
  zero_mval ce (Tstruct id) = MVstruct (map (fun m => (fst m, zero_mval ce (snd m))) members).
Proof. intros; apply default_mval_struct; auto. Qed.

Lemma undef_mval_struct:
  forall ce id members,
  wf_composites ce ->
  struct_members ce id = Some members ->
  undef_mval ce (Tstruct id) = MVstruct (map (fun m => (fst m, undef_mval ce (snd m))) members).
Proof. intros; apply default_mval_struct; auto. Qed.

Lemma default_mval_array:
  forall dflt ce t n, default_mval dflt ce (Tarray t n) = MVarray (repeat (default_mval dflt ce t) (Z.to_nat n)).
Proof. reflexivity. Qed.

Lemma default_mval_scalar:
  forall dflt ce ty, is_scalar_type ty = true -> default_mval dflt ce ty = MVscalar (dflt ty).
Proof. intros dflt ce ty H; destruct ty; try discriminate; reflexivity. Qed.

Lemma zero_val_has_type:
  forall ty, is_scalar_type ty = true -> val_has_type (zero_val ty) ty.
Proof.
  intros ty H; destruct ty as [| sz sg | sg | [|] | t | t n | args r | id ];
    try discriminate; simpl; auto;
    unfold norm_int, norm_long, wrap, wrap_signed, wrap_unsigned;
    try destruct sz; destruct sg; reflexivity.
Qed.

Lemma zero_mval_scalar_has_type:
  forall ce ty, is_scalar_type ty = true -> mval_has_type ce ty (zero_mval ce ty).
Proof.
  intros ce ty H. unfold zero_mval; rewrite default_mval_scalar by auto.
  constructor; auto. apply zero_val_has_type; auto.
Qed.

(** Zero values are well typed. *)
Lemma zero_mval_has_type:
  forall ce ty, wf_composites ce ->
  complete_type (composite_names ce) ty = true ->
  mval_has_type ce ty (zero_mval ce ty).
Proof.
  intros ce ty0 WF.
  destruct (composites_ok_inv ce [] WF) as [ND [_ MEM]].
  (* induction on the prefix of the environment that the type may use *)
  assert (Main: forall pre, (exists post, ce = pre ++ post) ->
            forall ty, complete_type (composite_names pre) ty = true ->
            mval_has_type ce ty (zero_mval ce ty)).
  { intros pre; induction pre as [|co pre IH] using rev_ind; intros [post E] ty Hty.
    - induction ty as [| sz sg | sg | fs | t IHt | t IHty n | args r IHr | id];
        simpl in Hty; try discriminate;
        try (apply zero_mval_scalar_has_type; reflexivity).
      + apply andb_prop in Hty as [Hn Ht]. unfold zero_mval; rewrite default_mval_array; fold (zero_mval ce t).
        constructor.
        * rewrite repeat_length. apply Z.leb_le in Hn. lia.
        * induction (Z.to_nat n); simpl; constructor; auto.
    - assert (IH': forall ty, complete_type (composite_names pre) ty = true ->
                              mval_has_type ce ty (zero_mval ce ty)).
      { apply IH. exists (co :: post). rewrite E, <- app_assoc. reflexivity. }
      induction ty as [| sz sg | sg | fs | t IHt | t IHty n | args r IHr | id];
        simpl in Hty; try discriminate;
        try (apply zero_mval_scalar_has_type; reflexivity).
      + apply andb_prop in Hty as [Hn Ht]. unfold zero_mval; rewrite default_mval_array; fold (zero_mval ce t).
        constructor.
        * rewrite repeat_length. apply Z.leb_le in Hn. lia.
        * specialize (IHty Ht). induction (Z.to_nat n); simpl; constructor; auto.
      + apply in_ident_spec in Hty. unfold composite_names in Hty.
        rewrite map_app, in_app_iff in Hty. simpl in Hty.
        destruct Hty as [Hin|[Hid|[]]].
        * apply IH'. simpl. apply in_ident_spec. exact Hin.
        * subst id.
          assert (FC: find_composite (co_name co) ce = Some co).
          { rewrite E, <- app_assoc. simpl.
            assert (ND2: NoDup (composite_names (pre ++ co :: post)))
              by (rewrite <- app_assoc in E; simpl in E; rewrite <- E; exact ND).
            clear -ND2. induction pre as [|c pre IHp]; simpl.
            - unfold find_composite; simpl. destruct (string_dec (co_name co) (co_name co)); congruence.
            - unfold find_composite in *; simpl.
              simpl in ND2. inversion ND2 as [|? ? Hc ND3]; subst.
              destruct (string_dec (co_name c) (co_name co)) as [Eq|_].
              + exfalso; apply Hc. rewrite Eq. unfold composite_names.
                rewrite map_app, in_app_iff; simpl; auto.
              + apply IHp; auto. }
          assert (SM: struct_members ce (co_name co) = Some (co_members co))
            by (unfold struct_members; rewrite FC; reflexivity).
          rewrite (zero_mval_struct ce _ _ WF SM).
          econstructor; [exact SM|].
          assert (E2: ce = pre ++ co :: post) by (rewrite E, <- app_assoc; reflexivity).
          destruct (MEM pre co post E2) as [_ Hc].
          assert (Hm: forall f t, In (f, t) (co_members co) ->
                      mval_has_type ce t (zero_mval ce t)).
          { intros f t Hin. apply IH'. rewrite <- (app_nil_r (composite_names pre)). apply (Hc f t Hin). }
          clear -Hm. induction (co_members co) as [|[f t] ms IHm]; simpl; constructor.
          -- apply (Hm f t); simpl; auto.
          -- apply IHm. intros f' t' Hin; apply (Hm f' t'); simpl; auto. }
  intros Hty. apply (Main ce); auto. exists []; rewrite app_nil_r; reflexivity.
Qed.
