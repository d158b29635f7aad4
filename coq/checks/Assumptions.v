(** The axiom gate: every main theorem must be closed under the global
    context.  `make proofs` counts the lines below that start with
    "Print Assumptions" and requires as many "Closed under the global context". *)
From ROSGen Require Import Errors.
Print Assumptions Errors.mmap_length.
