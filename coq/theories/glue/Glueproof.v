(** * Correctness proof for the generated glue functions (theorem T1) *)

(** For every well-formed node model [m] and its program [p]
    ([generate m = OK p]), the generated callbacks, [input_glue] and
    [output_glue_c] meet the specifications of [DDC]: [callback_ddc]
    (the paper's Figure 10), [input_glue_ddc] (Figure 12) and
    [output_glue_ddc].  The proofs run the bodies symbolically with
    [Copyproof.exec_copies]: each body is a sequence of copies, one per
    leaf or relation, into one destination block, from other blocks. *)

(** The proofs are in three files: [Gluefacts] (what they share),
    [Inputproof] (the callbacks, [input_glue]) and [Outputproof] (the
    output glue); this file states the theorems, and exports the three
    (files that load [Glueproof] see every lemma of the proof). *)

From Coq Require Import String List ZArith Bool Lia.
From ROSGen Require Import Errors Maps Syntax Values Operators Memory Environment Semantics NodeModel Wellformed Generator Generatorspec Generatorproof.
From ROSGen Require Import DDC Copyproof.
From ROSGen Require Export Gluefacts Inputproof Outputproof.
Import ListNotations.

(** ** The theorems *)

(** T1 for callbacks (the paper's Figure 10, for every model). *)
Theorem generate_callback_ddc:
  forall m p, generate m = OK p ->
  forall tp, In tp (subscribed m) -> callback_ddc m p tp.
Proof. intros m p GEN; apply generate_callback_ddc_aux; auto. Qed.

(** T1 for [input_glue] (the paper's Figure 12, for every model). *)
Theorem generate_input_glue_ddc:
  forall m p, generate m = OK p -> input_glue_ddc m p.
Proof. intros m p GEN; apply generate_input_glue_ddc_aux; auto. Qed.

(** T1 for the output glue of every published topic. *)
Theorem generate_output_glue_ddc:
  forall m p, generate m = OK p ->
  forall tp, In tp (published m) -> output_glue_ddc m p tp.
Proof. intros m p GEN; apply generate_output_glue_ddc_aux; auto. Qed.
