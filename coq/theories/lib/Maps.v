(** * Finite maps: binary tries keyed by positive numbers *)

(** The one finite-map implementation of the library, used for two
    purposes:
    - the memory ([Memory]): blocks are numbered by [positive]s, and a
      memory maps each live block to its contents ([ptree], [pget],
      [pset], [premove]);
    - the generator's tables ([Wellformed], [Generator]): names, paths
      and pairs are mapped to bit strings by the prefix-free encodings
      below ([enc_string], [enc_Z], [enc_pair], [enc_list]), and a bit
      string to a [positive] by the bijection [pos_of_bits]; [tget] and
      [tset] look up and update a map at such a key.  With them a model
      with thousands of relations is checked and translated in time linear
      in its size, without comparing every pair of names.
    Only the specifications ([pgss], [pgso], [pgrs], [pgro],
    [tget_tset_same], [tget_tset_other], [find_dup_None],
    [tmem_of_list], ...) matter to the proofs.  The trees compute under
    [vm_compute] and in extracted code. *)

From Coq Require Import String Ascii List ZArith Bool.
Import ListNotations.

(** ** Binary tries indexed by positive numbers (used by [Memory]) *)

Inductive ptree (A : Type) : Type :=
  | PLeaf
  | PNode (l : ptree A) (o : option A) (r : ptree A).

Arguments PLeaf {A}.
Arguments PNode {A} l o r.

Fixpoint pget {A : Type} (i : positive) (t : ptree A) {struct i} : option A :=
  match t with
  | PLeaf => None
  | PNode l o r =>
      match i with
      | xH => o
      | xO i' => pget i' l
      | xI i' => pget i' r
      end
  end.

Fixpoint pset {A : Type} (i : positive) (x : A) (t : ptree A) {struct i} : ptree A :=
  match t with
  | PLeaf =>
      match i with
      | xH => PNode PLeaf (Some x) PLeaf
      | xO i' => PNode (pset i' x PLeaf) None PLeaf
      | xI i' => PNode PLeaf None (pset i' x PLeaf)
      end
  | PNode l o r =>
      match i with
      | xH => PNode l (Some x) r
      | xO i' => PNode (pset i' x l) o r
      | xI i' => PNode l o (pset i' x r)
      end
  end.

Fixpoint premove {A : Type} (i : positive) (t : ptree A) {struct i} : ptree A :=
  match t with
  | PLeaf => PLeaf
  | PNode l o r =>
      match i with
      | xH => PNode l None r
      | xO i' => PNode (premove i' l) o r
      | xI i' => PNode l o (premove i' r)
      end
  end.

Lemma pget_leaf: forall A i, @pget A i PLeaf = None.
Proof. destruct i; reflexivity. Qed.

Lemma pgss: forall A i (x : A) t, pget i (pset i x t) = Some x.
Proof.
  induction i; destruct t; simpl; auto.
Qed.

Lemma pgso: forall A i j (x : A) t, i <> j -> pget i (pset j x t) = pget i t.
Proof.
  induction i; destruct j; destruct t; simpl; intros H;
    try rewrite pget_leaf; auto; try congruence;
    try (apply IHi; congruence);
    try (rewrite IHi; [apply pget_leaf | congruence]).
Qed.

Lemma pgrs: forall A i (t : ptree A), pget i (premove i t) = None.
Proof. induction i; destruct t; simpl; auto. Qed.

Lemma pgro: forall A i j (t : ptree A), i <> j -> pget i (premove j t) = pget i t.
Proof.
  induction i; destruct j; destruct t; simpl; intros H; auto; try congruence;
    apply IHi; congruence.
Qed.

(** ** Keys that are bit strings *)

(** A bit string as a positive number: the bits, least significant
    first, then a leading 1.  Every positive is the image of exactly one
    bit string. *)
Fixpoint pos_of_bits (k : list bool) : positive :=
  match k with
  | [] => xH
  | false :: k' => xO (pos_of_bits k')
  | true :: k' => xI (pos_of_bits k')
  end.

Lemma pos_of_bits_inj: forall k k', pos_of_bits k = pos_of_bits k' -> k = k'.
Proof.
  induction k as [|[|] k IH]; intros [|[|] k'] E; simpl in E; try discriminate; auto;
    injection E; intros E'; rewrite (IH _ E'); reflexivity.
Qed.

(** The value at a bit-string key, and the map updated there. *)
Definition tget {A : Type} (k : list bool) (t : ptree A) : option A := pget (pos_of_bits k) t.

Definition tset {A : Type} (k : list bool) (v : A) (t : ptree A) : ptree A :=
  pset (pos_of_bits k) v t.

Lemma tget_leaf: forall (A : Type) k, tget k (@PLeaf A) = None.
Proof. intros; apply pget_leaf. Qed.

Lemma tget_tset_same: forall (A : Type) k (v : A) t, tget k (tset k v t) = Some v.
Proof. intros; apply pgss. Qed.

Lemma tget_tset_other:
  forall (A : Type) k k' (v : A) t, k <> k' -> tget k' (tset k v t) = tget k' t.
Proof.
  intros A k k' v t N. apply pgso. intros E. apply N. symmetry. apply pos_of_bits_inj; auto.
Qed.

(** ** Maps built from association lists (the first binding wins) *)

Definition tmap_of_list {A B : Type} (enc : A -> list bool) (l : list (A * B)) : ptree B :=
  fold_right (fun kv t => tset (enc (fst kv)) (snd kv) t) PLeaf l.

(** The value of a key, or a default. *)
Definition tget_default {A : Type} (d : A) (k : list bool) (t : ptree A) : A :=
  match tget k t with Some v => v | None => d end.

(** ** Prefix-free encodings *)

(** An encoding is prefix-free when no code is a proper prefix of
    another; such encodings are injective and compose. *)
Definition prefix_free {A : Type} (enc : A -> list bool) : Prop :=
  forall a b r1 r2, enc a ++ r1 = enc b ++ r2 -> a = b /\ r1 = r2.

Lemma prefix_free_inj:
  forall (A : Type) (enc : A -> list bool), prefix_free enc ->
  forall a b, enc a = enc b -> a = b.
Proof.
  intros A enc P a b E. apply (P a b [] []). rewrite !app_nil_r; auto.
Qed.

Definition enc_ascii (c : ascii) : list bool :=
  match c with Ascii b0 b1 b2 b3 b4 b5 b6 b7 => [b0; b1; b2; b3; b4; b5; b6; b7] end.

Fixpoint enc_string (s : string) : list bool :=
  match s with
  | EmptyString => [false]
  | String c s' => true :: enc_ascii c ++ enc_string s'
  end.

Lemma enc_string_prefix_free: prefix_free enc_string.
Proof.
  intros a; induction a as [|c a IH]; intros [|c' b] r1 r2; simpl; intros E;
    try discriminate.
  - inversion E; auto.
  - destruct c as [b0 b1 b2 b3 b4 b5 b6 b7], c' as [b0' b1' b2' b3' b4' b5' b6' b7'].
    simpl in E. inversion E; subst.
    destruct (IH b r1 r2) as [-> ->]; auto.
Qed.

Fixpoint enc_pos (p : positive) : list bool :=
  match p with
  | xH => [false]
  | xO p' => true :: false :: enc_pos p'
  | xI p' => true :: true :: enc_pos p'
  end.

Lemma enc_pos_prefix_free: prefix_free enc_pos.
Proof.
  intros a; induction a as [a IH|a IH|]; intros [b|b|] r1 r2; simpl; intros E;
    inversion E; auto; destruct (IH b r1 r2) as [-> ->]; auto.
Qed.

Definition enc_Z (z : Z) : list bool :=
  match z with
  | Z0 => [false; false]
  | Zpos p => false :: true :: enc_pos p
  | Zneg p => true :: enc_pos p
  end.

Lemma enc_Z_prefix_free: prefix_free enc_Z.
Proof.
  intros [|a|a] [|b|b] r1 r2; simpl; intros E; inversion E; auto;
    destruct (enc_pos_prefix_free a b r1 r2) as [-> ->]; auto.
Qed.

Definition enc_pair {A B : Type} (ea : A -> list bool) (eb : B -> list bool) (x : A * B) : list bool :=
  ea (fst x) ++ eb (snd x).

Lemma enc_pair_prefix_free:
  forall (A B : Type) (ea : A -> list bool) (eb : B -> list bool),
  prefix_free ea -> prefix_free eb -> prefix_free (enc_pair ea eb).
Proof.
  intros A B ea eb Pa Pb [a1 b1] [a2 b2] r1 r2; unfold enc_pair; simpl.
  rewrite <- !app_assoc; intros E.
  destruct (Pa _ _ _ _ E) as [-> E']. destruct (Pb _ _ _ _ E') as [-> ->]; auto.
Qed.

Fixpoint enc_list {A : Type} (ea : A -> list bool) (l : list A) : list bool :=
  match l with
  | [] => [false]
  | x :: l' => true :: ea x ++ enc_list ea l'
  end.

Lemma enc_list_prefix_free:
  forall (A : Type) (ea : A -> list bool), prefix_free ea -> prefix_free (enc_list ea).
Proof.
  intros A ea Pa a; induction a as [|x a IH]; intros [|y b] r1 r2; simpl; intros E;
    try discriminate.
  - inversion E; auto.
  - inversion E as [E']. rewrite <- !app_assoc in E'.
    destruct (Pa _ _ _ _ E') as [-> E'']. destruct (IH _ _ _ E'') as [-> ->]; auto.
Qed.

(** ** Duplicates and membership *)

Section KEYED.

Variable A : Type.
Variable enc : A -> list bool.
Hypothesis enc_inj: forall a b, enc a = enc b -> a = b.

(** The first element of a list that occurs earlier in it. *)
Fixpoint find_dup_aux (seen : ptree unit) (l : list A) : option A :=
  match l with
  | [] => None
  | x :: l' =>
      match tget (enc x) seen with
      | Some _ => Some x
      | None => find_dup_aux (tset (enc x) tt seen) l'
      end
  end.

Definition find_dup (l : list A) : option A := find_dup_aux PLeaf l.

Lemma find_dup_aux_None:
  forall l seen,
  find_dup_aux seen l = None <-> NoDup l /\ (forall x, In x l -> tget (enc x) seen = None).
Proof.
  induction l as [|x l IH]; intros seen; simpl.
  - split; [intros _; split; [constructor|tauto]|auto].
  - destruct (tget (enc x) seen) as [[]|] eqn:G.
    + split; [discriminate|]. intros [_ H]. rewrite H in G; [discriminate|auto].
    + rewrite IH. split.
      * intros [ND H]. split.
        -- constructor; auto. intros Hx. specialize (H x Hx).
           rewrite tget_tset_same in H; discriminate.
        -- intros y [<-|Hy]; auto. specialize (H y Hy).
           destruct (list_eq_dec Bool.bool_dec (enc x) (enc y)) as [E|E].
           ++ rewrite E, tget_tset_same in H; discriminate.
           ++ rewrite tget_tset_other in H; auto.
      * intros [ND H]. inversion ND as [|? ? Hn ND']; subst. split; auto.
        intros y Hy. rewrite tget_tset_other; auto.
        intros E. apply enc_inj in E; subst; contradiction.
Qed.

Lemma find_dup_None: forall l, find_dup l = None <-> NoDup l.
Proof.
  intros l; unfold find_dup; rewrite find_dup_aux_None.
  split; [tauto|]. intros; split; auto. intros; apply tget_leaf.
Qed.

(** The set of the elements of a list, and membership. *)
Definition tset_of_list (l : list A) : ptree unit :=
  fold_right (fun x t => tset (enc x) tt t) PLeaf l.

Definition tmem (x : A) (s : ptree unit) : bool :=
  match tget (enc x) s with Some _ => true | None => false end.

Lemma tmem_of_list: forall x l, tmem x (tset_of_list l) = true <-> In x l.
Proof.
  unfold tmem; induction l as [|y l IH]; simpl.
  - rewrite tget_leaf. split; [discriminate|tauto].
  - destruct (list_eq_dec Bool.bool_dec (enc y) (enc x)) as [E|E].
    + rewrite E, tget_tset_same. apply enc_inj in E; subst; tauto.
    + rewrite tget_tset_other by auto. rewrite IH.
      split; [tauto|]. intros [<-|H]; [congruence|auto].
Qed.

End KEYED.

Arguments find_dup {A} enc l.
Arguments tset_of_list {A} enc l.
Arguments tmem {A} enc x s.
