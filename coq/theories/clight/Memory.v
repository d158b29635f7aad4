(** * The memory model *)

(** Memory is a finite map from blocks to typed structured values
    ([type * mval]), together with the next fresh block.  Every variable
    (global, addressable local, or the message handed to a callback) lives
    in its own block; a pointer is a block and a [path] of field
    selections and array subscripts inside the value stored there.
    Loads and stores read and replace the sub-value at a path.

    Why this abstraction is adequate for the emitted code (the generated
    glue of [Generator] and the programs of the tests):
    - no pointer arithmetic is ever emitted (array elements are reached
      by [Eindex] on an array l-value, never by adding to a pointer), so
      every pointer the program can build is a block plus a path;
    - no casts between pointer types, no unions and no [memcpy]: an
      object is only ever accessed at its own type, so a byte-level view
      could never be observed;
    - no address comparisons and no pointer-to-integer conversions, so
      the concrete addresses (and the order of blocks) are unobservable;
    - struct layout and padding are invisible to code that only accesses
      named fields and copies whole structs: a struct is the list of its
      members, a struct copy copies that list;
    - uninitialised reads do not matter: locals start with the right shape
      and every scalar [Vundef]; a computation that uses [Vundef] (a
      condition, a store, a cast) is stuck, which only makes the semantics
      stricter than C.
    The blocks of globals, locals and delivered messages are disjoint by
    construction ([alloc] always returns [mem_next] and increments it), so
    writes through one variable never affect another one.  The finite map
    is the binary trie on [positive] of [Maps] ([ptree]), so that the
    interpreter runs efficiently under [vm_compute]. *)

From Coq Require Import String List ZArith Bool Lia.
From ROSGen Require Import Maps Syntax Values.
Import ListNotations.
Local Open Scope Z_scope.

(** ** Sub-values at a path *)

(** Replace the first field named [f]. *)
Fixpoint set_field (f : ident) (v : mval) (l : list (ident * mval)) : list (ident * mval) :=
  match l with
  | [] => []
  | (g, x) :: l' => if ident_eq f g then (g, v) :: l' else (g, x) :: set_field f v l'
  end.

(** Replace the [n]-th element. *)
Fixpoint replace_nth {A : Type} (l : list A) (n : nat) (x : A) : list A :=
  match l, n with
  | [], _ => []
  | _ :: l', O => x :: l'
  | y :: l', S n' => y :: replace_nth l' n' x
  end.

(** The sub-value one step into [mv]. *)
Definition get_step (mv : mval) (s : step) : option mval :=
  match s, mv with
  | Sfield f, MVstruct fs => find_assoc f fs
  | Sindex i, MVarray es => if Z.leb 0 i then nth_error es (Z.to_nat i) else None
  | _, _ => None
  end.

(** Replace the sub-value one step into [mv] (which must exist). *)
Definition set_step (mv : mval) (s : step) (x : mval) : option mval :=
  match s, mv with
  | Sfield f, MVstruct fs =>
      match find_assoc f fs with
      | Some _ => Some (MVstruct (set_field f x fs))
      | None => None
      end
  | Sindex i, MVarray es =>
      if Z.leb 0 i && Nat.ltb (Z.to_nat i) (length es)
      then Some (MVarray (replace_nth es (Z.to_nat i) x))
      else None
  | _, _ => None
  end.

(** The sub-value at a path. *)
Fixpoint mval_get (mv : mval) (p : path) {struct p} : option mval :=
  match p with
  | [] => Some mv
  | s :: p' =>
      match get_step mv s with
      | Some x => mval_get x p'
      | None => None
      end
  end.

(** Replace the sub-value at a path (which must exist) by [v]. *)
Fixpoint mval_set (mv : mval) (p : path) (v : mval) {struct p} : option mval :=
  match p with
  | [] => Some v
  | s :: p' =>
      match get_step mv s with
      | Some x =>
          match mval_set x p' v with
          | Some x' => set_step mv s x'
          | None => None
          end
      | None => None
      end
  end.

(** Two paths are disjoint when neither is a prefix of the other: they
    designate non-overlapping sub-values. *)
Fixpoint path_disjoint (p q : path) : Prop :=
  match p, q with
  | s1 :: p', s2 :: q' => s1 <> s2 \/ path_disjoint p' q'
  | _, _ => False
  end.

Fixpoint path_disjointb (p q : path) : bool :=
  match p, q with
  | s1 :: p', s2 :: q' => if step_eq s1 s2 then path_disjointb p' q' else true
  | _, _ => false
  end.

Lemma path_disjointb_correct: forall p q, path_disjointb p q = true <-> path_disjoint p q.
Proof.
  induction p as [|s1 p IH]; destruct q as [|s2 q]; simpl; try (split; intros; first [discriminate | contradiction]).
  destruct (step_eq s1 s2) as [E|N].
  - rewrite IH. split; [auto|]. intros [H|H]; [contradiction|auto].
  - split; auto.
Qed.

Lemma path_disjoint_sym: forall p q, path_disjoint p q -> path_disjoint q p.
Proof.
  induction p as [|s1 p IH]; destruct q as [|s2 q]; simpl; auto.
  intros [H|H]; [left; congruence | right; auto].
Qed.

(** *** Properties of one step *)

Lemma find_assoc_set_field_same:
  forall f v l y, find_assoc f l = Some y -> find_assoc f (set_field f v l) = Some v.
Proof.
  induction l as [|[g x] l IH]; simpl; intros y H; try discriminate.
  destruct (string_dec f g) as [E|N].
  - subst; simpl. destruct (ident_eq g g); [|congruence]. simpl.
    destruct (string_dec g g); congruence.
  - destruct (ident_eq f g); [congruence|]. simpl.
    destruct (string_dec f g); [congruence|]. eauto.
Qed.

Lemma find_assoc_set_field_other:
  forall f g v l, g <> f -> find_assoc g (set_field f v l) = find_assoc g l.
Proof.
  induction l as [|[h x] l IH]; simpl; intros N; auto.
  destruct (ident_eq f h) as [E|E]; simpl.
  - subst h. destruct (string_dec g f); congruence.
  - destruct (string_dec g h); auto.
Qed.

Lemma set_field_find_assoc:
  forall f l x, find_assoc f l = Some x -> set_field f x l = l.
Proof.
  induction l as [|[g y] l IH]; simpl; intros x H; try discriminate.
  destruct (string_dec f g) as [E|N]; destruct (ident_eq f g); try congruence.
  f_equal; auto.
Qed.

Lemma map_fst_set_field:
  forall f v l, map fst (set_field f v l) = map fst l.
Proof.
  induction l as [|[g x] l IH]; simpl; auto.
  destruct (ident_eq f g); simpl; f_equal; auto.
Qed.

Lemma replace_nth_length:
  forall A (l : list A) n x, length (replace_nth l n x) = length l.
Proof. induction l; destruct n; simpl; auto. Qed.

Lemma nth_error_replace_same:
  forall A (l : list A) n x, (n < length l)%nat -> nth_error (replace_nth l n x) n = Some x.
Proof. induction l; destruct n; simpl; intros; auto; try lia. apply IHl; lia. Qed.

Lemma nth_error_replace_other:
  forall A (l : list A) n m x, n <> m -> nth_error (replace_nth l n x) m = nth_error l m.
Proof.
  induction l; destruct n, m; simpl; intros x H; auto; try congruence.
Qed.

Lemma replace_nth_nth_error:
  forall A (l : list A) n x, nth_error l n = Some x -> replace_nth l n x = l.
Proof.
  induction l; destruct n; simpl; intros x H; try discriminate.
  - inversion H; reflexivity.
  - f_equal; auto.
Qed.

Lemma get_set_step_same:
  forall mv s x mv', set_step mv s x = Some mv' -> get_step mv' s = Some x.
Proof.
  intros mv s x mv' H; destruct s as [f|i], mv as [v|fs|es]; simpl in H; try discriminate.
  - destruct (find_assoc f fs) eqn:E; inversion H; subst; simpl.
    eapply find_assoc_set_field_same; eauto.
  - destruct (Z.leb 0 i) eqn:Hi; simpl in H; try discriminate.
    destruct (Nat.ltb (Z.to_nat i) (length es)) eqn:Hl; inversion H; subst; simpl.
    rewrite Hi. apply nth_error_replace_same. apply Nat.ltb_lt; auto.
Qed.

Lemma get_set_step_other:
  forall mv s s' x mv', s <> s' -> set_step mv s x = Some mv' -> get_step mv' s' = get_step mv s'.
Proof.
  intros mv s s' x mv' N H; destruct s as [f|i], mv as [v|fs|es]; simpl in H; try discriminate.
  - destruct (find_assoc f fs) eqn:E; inversion H; subst.
    destruct s' as [g|j]; simpl; auto.
    apply find_assoc_set_field_other; congruence.
  - destruct (Z.leb 0 i) eqn:Hi; simpl in H; try discriminate.
    destruct (Nat.ltb (Z.to_nat i) (length es)) eqn:Hl; inversion H; subst.
    destruct s' as [g|j]; simpl; auto.
    destruct (Z.leb 0 j) eqn:Hj; auto.
    apply nth_error_replace_other.
    apply Z.leb_le in Hi; apply Z.leb_le in Hj. intros E; apply N. f_equal.
    apply Z2Nat.inj; auto.
Qed.

Lemma set_step_defined:
  forall mv s x y, get_step mv s = Some y -> exists mv', set_step mv s x = Some mv'.
Proof.
  intros mv s x y H; destruct s as [f|i], mv as [v|fs|es]; simpl in *; try discriminate.
  - rewrite H; eauto.
  - destruct (Z.leb 0 i); try discriminate. simpl.
    assert (Hl: (Z.to_nat i < length es)%nat) by (apply nth_error_Some; congruence).
    apply Nat.ltb_lt in Hl. rewrite Hl. eauto.
Qed.

Lemma set_step_get_defined:
  forall mv s x mv', set_step mv s x = Some mv' -> exists y, get_step mv s = Some y.
Proof.
  intros mv s x mv' H; destruct s as [f|i], mv as [v|fs|es]; simpl in *; try discriminate.
  - destruct (find_assoc f fs); try discriminate; eauto.
  - destruct (Z.leb 0 i); try discriminate. simpl in H.
    destruct (Nat.ltb (Z.to_nat i) (length es)) eqn:Hl; try discriminate.
    apply Nat.ltb_lt in Hl. apply nth_error_Some in Hl.
    destruct (nth_error es (Z.to_nat i)); eauto; congruence.
Qed.

Lemma set_step_same_value:
  forall mv s x, get_step mv s = Some x -> set_step mv s x = Some mv.
Proof.
  intros mv s x H; destruct s as [f|i], mv as [v|fs|es]; simpl in *; try discriminate.
  - rewrite H. rewrite set_field_find_assoc; auto.
  - destruct (Z.leb 0 i); try discriminate. simpl.
    assert (Hl: (Z.to_nat i < length es)%nat) by (apply nth_error_Some; congruence).
    apply Nat.ltb_lt in Hl. rewrite Hl. rewrite replace_nth_nth_error; auto.
Qed.

(** *** Properties of paths *)

Lemma mval_get_app:
  forall p q mv,
  mval_get mv (p ++ q) = match mval_get mv p with Some x => mval_get x q | None => None end.
Proof.
  induction p as [|s p IH]; simpl; intros q mv; auto.
  destruct (get_step mv s); auto.
Qed.

Lemma mval_set_defined:
  forall p mv v, (exists mv', mval_set mv p v = Some mv') <-> (exists x, mval_get mv p = Some x).
Proof.
  induction p as [|s p IH]; simpl; intros mv v.
  - split; eauto.
  - destruct (get_step mv s) as [y|] eqn:G.
    + rewrite <- (IH y v). split.
      * intros [mv' H]. destruct (mval_set y p v); try discriminate; eauto.
      * intros [y' H]. rewrite H. eapply set_step_defined; eauto.
    + split; intros [? H]; discriminate.
Qed.

(** Load after store at the same path. *)
Lemma mval_get_set_same:
  forall p mv v mv', mval_set mv p v = Some mv' -> mval_get mv' p = Some v.
Proof.
  induction p as [|s p IH]; simpl; intros mv v mv' H.
  - congruence.
  - destruct (get_step mv s) as [y|]; try discriminate.
    destruct (mval_set y p v) as [y'|] eqn:S; try discriminate.
    rewrite (get_set_step_same _ _ _ _ H). eauto.
Qed.

(** Load after store at a disjoint path. *)
Lemma mval_get_set_disjoint:
  forall p q mv v mv', path_disjoint p q ->
  mval_set mv p v = Some mv' -> mval_get mv' q = mval_get mv q.
Proof.
  induction p as [|s p IH]; destruct q as [|s' q]; simpl; intros mv v mv' D H; try contradiction.
  destruct (get_step mv s) as [y|] eqn:G; try discriminate.
  destruct (mval_set y p v) as [y'|] eqn:S; try discriminate.
  destruct (step_eq s s') as [E|N].
  - subst s'. destruct D as [D|D]; [congruence|].
    rewrite (get_set_step_same _ _ _ _ H), G. eapply IH; eauto.
  - rewrite (get_set_step_other _ _ _ _ _ N H). reflexivity.
Qed.

(** Store at an extension [p ++ q] of a path [p]: the value at [p] is
    updated at [q]. *)
Lemma mval_get_set_prefix:
  forall p q mv v mv', mval_set mv (p ++ q) v = Some mv' ->
  exists x x', mval_get mv p = Some x /\ mval_set x q v = Some x' /\ mval_get mv' p = Some x'.
Proof.
  induction p as [|s p IH]; simpl; intros q mv v mv' H.
  - exists mv, mv'; auto.
  - destruct (get_step mv s) as [y|] eqn:G; try discriminate.
    destruct (mval_set y (p ++ q) v) as [y'|] eqn:S; try discriminate.
    destruct (IH _ _ _ _ S) as [x [x' [A [B C]]]].
    exists x, x'. rewrite (get_set_step_same _ _ _ _ H). auto.
Qed.

(** Load at an extension of the path stored at reads into the stored
    value. *)
Lemma mval_get_set_extension:
  forall p q mv v mv', mval_set mv p v = Some mv' -> mval_get mv' (p ++ q) = mval_get v q.
Proof.
  intros p q mv v mv' H. rewrite mval_get_app. rewrite (mval_get_set_same _ _ _ _ H). reflexivity.
Qed.

(** Storing the value already there changes nothing. *)
Lemma mval_set_same_value:
  forall p mv x, mval_get mv p = Some x -> mval_set mv p x = Some mv.
Proof.
  induction p as [|s p IH]; simpl; intros mv x H.
  - congruence.
  - destruct (get_step mv s) as [y|] eqn:G; try discriminate.
    rewrite (IH _ _ H). apply set_step_same_value; auto.
Qed.

(** ** Memory states *)

Record mem : Type := mkmem {
  mem_contents : ptree (type * mval);   (**r the live blocks *)
  mem_next : block                      (**r the next block [alloc] returns *)
}.

Definition empty : mem := mkmem PLeaf 1%positive.

(** The type and value of block [b], if it is live. *)
Definition get_block (m : mem) (b : block) : option (type * mval) := pget b (mem_contents m).

(** Allocate a fresh block holding [mv] of type [ty]. *)
Definition alloc (m : mem) (ty : type) (mv : mval) : mem * block :=
  (mkmem (pset (mem_next m) (ty, mv) (mem_contents m)) (Pos.succ (mem_next m)), mem_next m).

(** Deallocate block [b]. *)
Definition free (m : mem) (b : block) : mem :=
  mkmem (premove b (mem_contents m)) (mem_next m).

(** The sub-value at path [p] of block [b]. *)
Definition load_path (m : mem) (b : block) (p : path) : option mval :=
  match get_block m b with
  | Some (_, mv) => mval_get mv p
  | None => None
  end.

(** Replace the sub-value at path [p] of block [b] by [v]; the sub-value
    must exist.  A whole-struct copy is a [store_path] of an [MVstruct]. *)
Definition store_path (m : mem) (b : block) (p : path) (v : mval) : option mem :=
  match get_block m b with
  | Some (ty, mv) =>
      match mval_set mv p v with
      | Some mv' => Some (mkmem (pset b (ty, mv') (mem_contents m)) (mem_next m))
      | None => None
      end
  | None => None
  end.

(** Scalar load: the value of scalar type [ty] at [p] in [b]. *)
Definition load (ty : type) (m : mem) (b : block) (p : path) : option val :=
  if is_scalar_type ty then
    match load_path m b p with
    | Some (MVscalar v) => Some v
    | _ => None
    end
  else None.

(** Scalar store: [v] converted to the scalar type [ty] (wrapping
    integers around) is stored at [p] in [b]. *)
Definition store (ty : type) (m : mem) (b : block) (p : path) (v : val) : option mem :=
  match sem_cast v ty with
  | Some v' => store_path m b p (MVscalar v')
  | None => None
  end.

(** All blocks at or above [mem_next] are free: [alloc] returns a fresh
    block. *)
Definition mem_wf (m : mem) : Prop :=
  forall b, (mem_next m <= b)%positive -> get_block m b = None.

(** ** Properties of memory operations *)

Lemma get_block_empty: forall b, get_block empty b = None.
Proof. intros; apply pget_leaf. Qed.

Lemma mem_wf_empty: mem_wf empty.
Proof. intros b _; apply get_block_empty. Qed.

Lemma alloc_result: forall m ty mv m' b, alloc m ty mv = (m', b) -> b = mem_next m.
Proof. unfold alloc; intros; congruence. Qed.

Lemma alloc_next: forall m ty mv m' b, alloc m ty mv = (m', b) -> mem_next m' = Pos.succ (mem_next m).
Proof. unfold alloc; intros m ty mv m' b H; inversion H; reflexivity. Qed.

Lemma get_block_alloc_same:
  forall m ty mv m' b, alloc m ty mv = (m', b) -> get_block m' b = Some (ty, mv).
Proof. unfold alloc, get_block; intros m ty mv m' b H; inversion H; subst; simpl; apply pgss. Qed.

Lemma get_block_alloc_other:
  forall m ty mv m' b b', alloc m ty mv = (m', b) -> b' <> b -> get_block m' b' = get_block m b'.
Proof. unfold alloc, get_block; intros m ty mv m' b b' H N; inversion H; subst; simpl; apply pgso; auto. Qed.

Lemma alloc_fresh:
  forall m ty mv m' b, mem_wf m -> alloc m ty mv = (m', b) -> get_block m b = None.
Proof. intros m ty mv m' b W H. rewrite (alloc_result _ _ _ _ _ H). apply W. lia. Qed.

Lemma mem_wf_alloc:
  forall m ty mv m' b, mem_wf m -> alloc m ty mv = (m', b) -> mem_wf m'.
Proof.
  intros m ty mv m' b W H b' Hb'. rewrite (alloc_next _ _ _ _ _ H) in Hb'.
  rewrite (get_block_alloc_other _ _ _ _ _ _ H).
  - apply W; lia.
  - rewrite (alloc_result _ _ _ _ _ H). lia.
Qed.

Lemma load_path_alloc_same:
  forall m ty mv m' b p, alloc m ty mv = (m', b) -> load_path m' b p = mval_get mv p.
Proof. intros; unfold load_path; erewrite get_block_alloc_same; eauto. Qed.

Lemma load_path_alloc_other:
  forall m ty mv m' b b' p, alloc m ty mv = (m', b) -> b' <> b -> load_path m' b' p = load_path m b' p.
Proof. intros; unfold load_path; erewrite get_block_alloc_other; eauto. Qed.

Lemma get_block_free_same: forall m b, get_block (free m b) b = None.
Proof. intros; apply pgrs. Qed.

Lemma get_block_free_other: forall m b b', b' <> b -> get_block (free m b) b' = get_block m b'.
Proof. intros; apply pgro; auto. Qed.

Lemma free_next: forall m b, mem_next (free m b) = mem_next m.
Proof. reflexivity. Qed.

Lemma mem_wf_free: forall m b, mem_wf m -> mem_wf (free m b).
Proof.
  intros m b W b' Hb'. destruct (Pos.eq_dec b' b) as [E|N].
  - subst; apply get_block_free_same.
  - rewrite get_block_free_other; auto.
Qed.

Lemma load_path_free_same: forall m b p, load_path (free m b) b p = None.
Proof. intros; unfold load_path; rewrite get_block_free_same; auto. Qed.

Lemma load_path_free_other:
  forall m b b' p, b' <> b -> load_path (free m b) b' p = load_path m b' p.
Proof. intros; unfold load_path; rewrite get_block_free_other; auto. Qed.

Lemma store_path_next:
  forall m b p v m', store_path m b p v = Some m' -> mem_next m' = mem_next m.
Proof.
  unfold store_path; intros m b p v m' H.
  destruct (get_block m b) as [[ty mv]|]; try discriminate.
  destruct (mval_set mv p v); inversion H; reflexivity.
Qed.

Lemma get_block_store_same:
  forall m b p v m', store_path m b p v = Some m' ->
  exists ty mv mv', get_block m b = Some (ty, mv) /\ mval_set mv p v = Some mv'
                    /\ get_block m' b = Some (ty, mv').
Proof.
  unfold store_path; intros m b p v m' H.
  destruct (get_block m b) as [[ty mv]|]; try discriminate.
  destruct (mval_set mv p v) as [mv'|] eqn:S; inversion H; subst.
  exists ty, mv, mv'; split; auto; split; auto. unfold get_block; simpl; apply pgss.
Qed.

Lemma get_block_store_other:
  forall m b p v m' b', store_path m b p v = Some m' -> b' <> b -> get_block m' b' = get_block m b'.
Proof.
  unfold store_path; intros m b p v m' b' H N.
  destruct (get_block m b) as [[ty mv]|]; try discriminate.
  destruct (mval_set mv p v); inversion H; subst. unfold get_block; simpl; apply pgso; auto.
Qed.

Lemma mem_wf_store:
  forall m b p v m', mem_wf m -> store_path m b p v = Some m' -> mem_wf m'.
Proof.
  intros m b p v m' W H b' Hb'. rewrite (store_path_next _ _ _ _ _ H) in Hb'.
  destruct (Pos.eq_dec b' b) as [E|N].
  - subst. destruct (get_block_store_same _ _ _ _ _ H) as [ty [mv [mv' [G _]]]].
    rewrite W in G; [discriminate | auto].
  - rewrite (get_block_store_other _ _ _ _ _ _ H N). apply W; auto.
Qed.

(** A store succeeds exactly when there is something at the path. *)
Lemma store_path_defined:
  forall m b p v, (exists m', store_path m b p v = Some m') <-> (exists x, load_path m b p = Some x).
Proof.
  intros m b p v; unfold store_path, load_path.
  destruct (get_block m b) as [[ty mv]|].
  - rewrite <- (mval_set_defined p mv v). split; intros [x H].
    + destruct (mval_set mv p v); eauto; discriminate.
    + rewrite H; eauto.
  - split; intros [x H]; discriminate.
Qed.

(** Load after store, same block and path. *)
Lemma load_path_store_same:
  forall m b p v m', store_path m b p v = Some m' -> load_path m' b p = Some v.
Proof.
  intros m b p v m' H. destruct (get_block_store_same _ _ _ _ _ H) as [ty [mv [mv' [A [B C]]]]].
  unfold load_path; rewrite C. eapply mval_get_set_same; eauto.
Qed.

(** Load after store, another block. *)
Lemma load_path_store_other_block:
  forall m b p v m' b' p', store_path m b p v = Some m' -> b' <> b ->
  load_path m' b' p' = load_path m b' p'.
Proof.
  intros; unfold load_path; erewrite get_block_store_other; eauto.
Qed.

(** Load after store, same block, disjoint path. *)
Lemma load_path_store_disjoint:
  forall m b p v m' p', store_path m b p v = Some m' -> path_disjoint p p' ->
  load_path m' b p' = load_path m b p'.
Proof.
  intros m b p v m' p' H D. destruct (get_block_store_same _ _ _ _ _ H) as [ty [mv [mv' [A [B C]]]]].
  unfold load_path; rewrite A, C. eapply mval_get_set_disjoint; eauto.
Qed.

(** Load after store: everything that does not overlap the stored
    sub-value is unchanged. *)
Lemma load_path_store_unchanged:
  forall m b p v m' b' p', store_path m b p v = Some m' -> (b' <> b \/ path_disjoint p p') ->
  load_path m' b' p' = load_path m b' p'.
Proof.
  intros m b p v m' b' p' H [N|D].
  - eapply load_path_store_other_block; eauto.
  - destruct (Pos.eq_dec b' b) as [E|N]; [subst; eapply load_path_store_disjoint; eauto|].
    eapply load_path_store_other_block; eauto.
Qed.

(** Store at a sub-path, then load a prefix: the update is seen. *)
Lemma load_path_store_prefix:
  forall m b p q v m', store_path m b (p ++ q) v = Some m' ->
  exists x x', load_path m b p = Some x /\ mval_set x q v = Some x' /\ load_path m' b p = Some x'.
Proof.
  intros m b p q v m' H. destruct (get_block_store_same _ _ _ _ _ H) as [ty [mv [mv' [A [B C]]]]].
  unfold load_path; rewrite A, C. eapply mval_get_set_prefix; eauto.
Qed.

(** Store, then load an extension of the path: reads into the stored
    value. *)
Lemma load_path_store_extension:
  forall m b p q v m', store_path m b p v = Some m' -> load_path m' b (p ++ q) = mval_get v q.
Proof.
  intros m b p q v m' H. destruct (get_block_store_same _ _ _ _ _ H) as [ty [mv [mv' [A [B C]]]]].
  unfold load_path; rewrite C. eapply mval_get_set_extension; eauto.
Qed.

Lemma load_path_app:
  forall m b p q, load_path m b (p ++ q) =
  match load_path m b p with Some x => mval_get x q | None => None end.
Proof.
  intros; unfold load_path. destruct (get_block m b) as [[ty mv]|]; auto. apply mval_get_app.
Qed.

(** Scalar loads and stores. *)
Lemma load_store_same:
  forall ty m b p v v' m', is_scalar_type ty = true ->
  store ty m b p v = Some m' -> sem_cast v ty = Some v' -> load ty m' b p = Some v'.
Proof.
  unfold store, load; intros ty m b p v v' m' Hs H C. rewrite C in H. rewrite Hs.
  rewrite (load_path_store_same _ _ _ _ _ H). reflexivity.
Qed.

Lemma store_unchanged:
  forall ty m b p v m' b' p', store ty m b p v = Some m' -> (b' <> b \/ path_disjoint p p') ->
  load_path m' b' p' = load_path m b' p'.
Proof.
  unfold store; intros ty m b p v m' b' p' H D.
  destruct (sem_cast v ty); try discriminate. eapply load_path_store_unchanged; eauto.
Qed.

Lemma store_next:
  forall ty m b p v m', store ty m b p v = Some m' -> mem_next m' = mem_next m.
Proof.
  unfold store; intros ty m b p v m' H.
  destruct (sem_cast v ty); try discriminate. eapply store_path_next; eauto.
Qed.

(** ** Types along paths *)

(** The type one step into a value of type [ty]; array subscripts must be
    in bounds. *)
Definition type_step (ce : composite_env) (ty : type) (s : step) : option type :=
  match s, ty with
  | Sfield f, Tstruct id =>
      match struct_members ce id with
      | Some members => field_type f members
      | None => None
      end
  | Sindex i, Tarray t n => if Z.leb 0 i && Z.ltb i n then Some t else None
  | _, _ => None
  end.

(** The type of the sub-value at a path. *)
Fixpoint type_at (ce : composite_env) (ty : type) (p : path) : option type :=
  match p with
  | [] => Some ty
  | s :: p' =>
      match type_step ce ty s with
      | Some t => type_at ce t p'
      | None => None
      end
  end.

Lemma type_at_app:
  forall ce p q ty, type_at ce ty (p ++ q) =
  match type_at ce ty p with Some t => type_at ce t q | None => None end.
Proof.
  induction p as [|s p IH]; simpl; intros; auto. destruct (type_step ce ty s); auto.
Qed.

Lemma fields_have_type_find:
  forall ce members fs f t, fields_have_type ce members fs -> find_assoc f members = Some t ->
  exists x, find_assoc f fs = Some x /\ mval_has_type ce t x.
Proof.
  intros ce members fs f t H; induction H as [|g tg mv ms fs' Hmv Hfs IH]; simpl; intros E; try discriminate.
  destruct (string_dec f g); [inversion E; subst; eauto | auto].
Qed.

Lemma elems_have_type_nth:
  forall ce t es n, elems_have_type ce t es -> (n < length es)%nat ->
  exists x, nth_error es n = Some x /\ mval_has_type ce t x.
Proof.
  intros ce t es n H; revert n; induction H as [|t' mv es' Hmv Hes IH]; simpl; intros n Hn; [lia|].
  destruct n; simpl; eauto. apply IH; lia.
Qed.

Lemma get_step_has_type:
  forall ce ty mv s t, mval_has_type ce ty mv -> type_step ce ty s = Some t ->
  exists x, get_step mv s = Some x /\ mval_has_type ce t x.
Proof.
  intros ce ty mv s t H T;
    inversion H as [ty' v Hs Hv | id members fs SM Hf | t' n es Hn He]; subst.
  - destruct ty; try discriminate Hs; destruct s; discriminate T.
  - destruct s as [f|i]; simpl in T; try discriminate.
    rewrite SM in T. simpl. eapply fields_have_type_find; eauto.
  - destruct s as [f|i]; simpl in T; try discriminate.
    destruct (Z.leb 0 i) eqn:Hi; simpl in T; try discriminate.
    destruct (Z.ltb i (Z.of_nat (length es))) eqn:Hl; inversion T; subst.
    simpl. rewrite Hi. apply elems_have_type_nth; auto.
    apply Z.leb_le in Hi; apply Z.ltb_lt in Hl. lia.
Qed.

(** A well-typed value has a well-typed sub-value at every path that has
    a type. *)
Lemma mval_get_has_type:
  forall ce p ty mv t, mval_has_type ce ty mv -> type_at ce ty p = Some t ->
  exists x, mval_get mv p = Some x /\ mval_has_type ce t x.
Proof.
  induction p as [|s p IH]; simpl; intros ty mv t H T.
  - inversion T; subst; eauto.
  - destruct (type_step ce ty s) as [t1|] eqn:T1; try discriminate.
    destruct (get_step_has_type _ _ _ _ _ H T1) as [x [G Hx]].
    rewrite G. eapply IH; eauto.
Qed.

Lemma fields_have_type_set:
  forall ce members fs f t v, fields_have_type ce members fs -> find_assoc f members = Some t ->
  mval_has_type ce t v -> fields_have_type ce members (set_field f v fs).
Proof.
  intros ce members fs f t v H; induction H as [|g tg mv ms fs' Hmv Hfs IH]; simpl; intros E Hv; try discriminate.
  destruct (string_dec f g) as [Eq|N]; destruct (ident_eq f g); try congruence.
  - inversion E; subst. constructor; auto.
  - constructor; auto.
Qed.

Lemma elems_have_type_replace:
  forall ce t es n v, elems_have_type ce t es -> mval_has_type ce t v ->
  elems_have_type ce t (replace_nth es n v).
Proof.
  intros ce t es n v H; revert n; induction H as [|t' mv es' Hmv Hes IH]; simpl; intros n Hv.
  - constructor.
  - destruct n; constructor; auto.
Qed.

Lemma set_step_has_type:
  forall ce ty mv s t v mv', mval_has_type ce ty mv -> type_step ce ty s = Some t ->
  mval_has_type ce t v -> set_step mv s v = Some mv' -> mval_has_type ce ty mv'.
Proof.
  intros ce ty mv s t v mv' H T Hv S;
    inversion H as [ty' v' Hs Hv' | id members fs SM Hf | t' n es Hn He]; subst.
  - destruct ty; try discriminate Hs; destruct s; discriminate T.
  - destruct s as [f|i]; simpl in T, S; try discriminate.
    rewrite SM in T. destruct (find_assoc f fs); inversion S; subst.
    econstructor; eauto. eapply fields_have_type_set; eauto.
  - destruct s as [f|i]; simpl in T, S; try discriminate.
    destruct (Z.leb 0 i) eqn:Hi; simpl in T, S; try discriminate.
    destruct (Z.ltb i (Z.of_nat (length es))); inversion T; subst.
    destruct (Nat.ltb (Z.to_nat i) (length es)); inversion S; subst.
    constructor.
    + rewrite replace_nth_length; auto.
    + apply elems_have_type_replace; auto.
Qed.

(** Storing a well-typed value at a typed path succeeds and keeps the
    whole value well typed. *)
Lemma mval_set_has_type:
  forall ce p ty mv t v, mval_has_type ce ty mv -> type_at ce ty p = Some t ->
  mval_has_type ce t v ->
  exists mv', mval_set mv p v = Some mv' /\ mval_has_type ce ty mv'.
Proof.
  induction p as [|s p IH]; simpl; intros ty mv t v H T Hv.
  - inversion T; subst; eauto.
  - destruct (type_step ce ty s) as [t1|] eqn:T1; try discriminate.
    destruct (get_step_has_type _ _ _ _ _ H T1) as [x [G Hx]].
    rewrite G. destruct (IH _ _ _ _ Hx T Hv) as [x' [S Hx']]. rewrite S.
    destruct (set_step_defined mv s x' x G) as [mv' S'].
    exists mv'; split; auto. eapply set_step_has_type; eauto.
Qed.

(** Sub-values of zero values are zero values. *)
Lemma complete_type_step:
  forall ce ty s t, wf_composites ce -> complete_type (composite_names ce) ty = true ->
  type_step ce ty s = Some t -> complete_type (composite_names ce) t = true.
Proof.
  intros ce ty s t WF C T; destruct s as [f|i], ty; simpl in T; try discriminate.
  - unfold struct_members in T. destruct (find_composite id ce) as [co|] eqn:FC; try discriminate.
    destruct (find_composite_split _ _ _ FC) as [_ [pre [post [E _]]]].
    destruct (composites_ok_inv ce [] WF) as [_ [_ MEM]].
    destruct (MEM pre co post E) as [_ Hc].
    unfold field_type in T. assert (Hin: In (f, t) (co_members co)).
    { clear -T. induction (co_members co) as [|[g u] l IH]; simpl in *; try discriminate.
      destruct (string_dec f g); [inversion T; subst; auto | auto]. }
    eapply complete_type_incl; [|apply (Hc f t Hin)].
    intros x; rewrite app_nil_r, E. unfold composite_names; rewrite map_app, in_app_iff; auto.
  - destruct (Z.leb 0 i && Z.ltb i n); inversion T; subst.
    simpl in C. apply andb_prop in C as [_ C]; auto.
Qed.

Lemma find_assoc_map_zero:
  forall (g : type -> mval) f members t,
  find_assoc f members = Some t ->
  find_assoc f (map (fun m => (fst m, g (snd m))) members) = Some (g t).
Proof.
  induction members as [|[h u] l IH]; simpl; intros t H; try discriminate.
  destruct (string_dec f h); [inversion H; subst; auto | auto].
Qed.

Lemma mval_get_zero:
  forall ce p ty t, wf_composites ce -> complete_type (composite_names ce) ty = true ->
  type_at ce ty p = Some t -> mval_get (zero_mval ce ty) p = Some (zero_mval ce t).
Proof.
  induction p as [|s p IH]; simpl; intros ty t WF C T.
  - congruence.
  - destruct (type_step ce ty s) as [t1|] eqn:T1; try discriminate.
    assert (C1: complete_type (composite_names ce) t1 = true) by (eapply complete_type_step; eauto).
    rewrite <- (IH t1 t WF C1 T).
    destruct s as [f|i], ty; simpl in T1; try discriminate.
    + destruct (struct_members ce id) as [members|] eqn:SM; try discriminate.
      rewrite (zero_mval_struct ce id members WF SM). simpl.
      rewrite (find_assoc_map_zero (zero_mval ce) f members t1 T1). reflexivity.
    + destruct (Z.leb 0 i) eqn:Hi; simpl in T1; try discriminate.
      destruct (Z.ltb i n) eqn:Hl; inversion T1; subst.
      unfold zero_mval at 1. rewrite default_mval_array. simpl. rewrite Hi.
      apply Z.leb_le in Hi; apply Z.ltb_lt in Hl.
      rewrite nth_error_repeat; [reflexivity|]. lia.
Qed.

Lemma load_spec:
  forall ty m b p v, is_scalar_type ty = true -> load_path m b p = Some (MVscalar v) ->
  load ty m b p = Some v.
Proof. unfold load; intros ty m b p v S L; rewrite S, L; reflexivity. Qed.

Lemma store_spec:
  forall ty m b p v v', sem_cast v ty = Some v' ->
  store ty m b p v = store_path m b p (MVscalar v').
Proof. unfold store; intros ty m b p v v' C; rewrite C; reflexivity. Qed.
