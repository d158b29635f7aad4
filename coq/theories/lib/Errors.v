(** * The error monad *)

(** Computations that may fail with a message, as in CompCert's
    [common/Errors.v] (written anew for this project).  Messages are lists of
    pieces so that a failing generator step can name what is wrong:
    [Error (MSG "Generator.gen_copy: unknown field " :: CTX f :: nil)]. *)

From Coq Require Import String List.
Import ListNotations.

Inductive errcode : Type :=
  | MSG (s : string)   (**r a fixed part of the message *)
  | CTX (s : string).  (**r a name from the model (printed quoted) *)

Definition errmsg : Type := list errcode.

Inductive res (A : Type) : Type :=
  | OK (x : A)
  | Error (msg : errmsg).

Arguments OK {A} x.
Arguments Error {A} msg.

Definition bind {A B : Type} (f : res A) (g : A -> res B) : res B :=
  match f with
  | OK x => g x
  | Error msg => Error msg
  end.

Definition bind2 {A B C : Type} (f : res (A * B)) (g : A -> B -> res C) : res C :=
  match f with
  | OK (x, y) => g x y
  | Error msg => Error msg
  end.

Declare Scope error_monad_scope.

Notation "'do' X <- A ; B" := (bind A (fun X => B))
  (at level 200, X name, A at level 100, B at level 200) : error_monad_scope.
Notation "'do' ( X , Y ) <- A ; B" := (bind2 A (fun X Y => B))
  (at level 200, X name, Y name, A at level 100, B at level 200) : error_monad_scope.

Local Open Scope error_monad_scope.

(** [mmap f l] applies [f] to every element of [l], failing at the first error. *)
Fixpoint mmap {A B : Type} (f : A -> res B) (l : list A) : res (list B) :=
  match l with
  | [] => OK []
  | x :: l' => do y <- f x; do l'' <- mmap f l'; OK (y :: l'')
  end.

(** Fail unless [b] holds. *)
Definition assertion (b : bool) (msg : errmsg) : res unit :=
  if b then OK tt else Error msg.

(** Render an error message as one line. *)
Fixpoint string_of_errmsg (m : errmsg) : string :=
  match m with
  | [] => ""
  | MSG s :: m' => s ++ string_of_errmsg m'
  | CTX s :: m' => "'" ++ s ++ "'" ++ string_of_errmsg m'
  end.

Lemma bind_inversion:
  forall (A B : Type) (f : res A) (g : A -> res B) (y : B),
  bind f g = OK y -> exists x, f = OK x /\ g x = OK y.
Proof.
  intros A B f g y; destruct f as [x|m]; simpl; [eauto | discriminate].
Qed.

Lemma bind2_inversion:
  forall (A B C : Type) (f : res (A * B)) (g : A -> B -> res C) (z : C),
  bind2 f g = OK z -> exists x y, f = OK (x, y) /\ g x y = OK z.
Proof.
  intros A B C f g z; destruct f as [[x y]|m]; simpl; [eauto | discriminate].
Qed.

Theorem mmap_length:
  forall (A B : Type) (f : A -> res B) l l', mmap f l = OK l' -> length l' = length l.
Proof.
  induction l as [|x l IH]; simpl; intros l' H.
  - inversion H; reflexivity.
  - destruct (f x) eqn:E; simpl in H; try discriminate.
    destruct (mmap f l) eqn:E2; simpl in H; try discriminate.
    inversion H; subst; simpl; f_equal; auto.
Qed.

(** [monadInv H] takes apart a hypothesis [H : (do x <- a; b) = OK y]. *)
Ltac monadInv1 H :=
  match type of H with
  | (OK _ = OK _) => inversion H; clear H; try subst
  | (Error _ = OK _) => discriminate
  | (bind ?F ?G = OK ?X) =>
      let x := fresh "x" in let EQ1 := fresh "EQ" in let EQ2 := fresh "EQ" in
      destruct (bind_inversion _ _ F G X H) as [x [EQ1 EQ2]]; clear H;
      try (monadInv1 EQ2)
  | (bind2 ?F ?G = OK ?X) =>
      let x1 := fresh "x" in let x2 := fresh "x" in
      let EQ1 := fresh "EQ" in let EQ2 := fresh "EQ" in
      destruct (bind2_inversion _ _ _ F G X H) as [x1 [x2 [EQ1 EQ2]]]; clear H;
      try (monadInv1 EQ2)
  end.

Ltac monadInv H :=
  match type of H with
  | (OK _ = OK _) => monadInv1 H
  | (Error _ = OK _) => monadInv1 H
  | (bind _ _ = OK _) => monadInv1 H
  | (bind2 _ _ = OK _) => monadInv1 H
  | (?F _ = OK _) => unfold F in H; monadInv1 H
  | (?F _ _ = OK _) => unfold F in H; monadInv1 H
  | (?F _ _ _ = OK _) => unfold F in H; monadInv1 H
  end.
