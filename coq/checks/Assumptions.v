(** The axiom gate: every main theorem must be closed under the global
    context.  `make proofs` counts the lines below that start with
    "Print Assumptions" and requires as many "Closed under the global context". *)
From ROSGen Require Import Errors.
Print Assumptions Errors.mmap_length.
From ROSGen Require Interpproof.
(* T5: the interpreter's results are results of the big-step semantics. *)
Print Assumptions Interpproof.interp_sound.
Print Assumptions Interpproof.run_program_sound.
(* The semantics is deterministic; the typing checker is sound. *)
Print Assumptions Semantics.semantics_determ.
From ROSGen Require Typing.
Print Assumptions Typing.check_program_correct.
From ROSGen Require FloatBits.
(* Float bit patterns: decoding and encoding are inverse, without axioms. *)
Print Assumptions FloatBits.bits_of_float64_of_bits.
Print Assumptions FloatBits.float64_of_bits_of_float64.
Print Assumptions FloatBits.bits_of_float32_of_bits.
Print Assumptions FloatBits.float32_of_bits_of_float32.
From ROSGen Require Generatorproof.
(* T4: generate accepts exactly the well-formed models; wf_check is wf. *)
Print Assumptions Generatorproof.generate_complete.
Print Assumptions Generatorproof.generate_sound.
Print Assumptions Generatorproof.wf_check_wf.
(* Leaves of a message: exactly its scalar paths, each once. *)
From ROSGen Require Generatorspec.
Print Assumptions Generatorspec.leaves_spec.
Print Assumptions Generatorspec.leaves_nodup.
(* T3 (paper Section 6): relation consistency (Fig. 15), valid assignment
   via type checking (Fig. 16), preservation. *)
Print Assumptions Generatorproof.relation_consistency_input_glue.
Print Assumptions Generatorproof.relation_consistency_output_glue.
Print Assumptions Generatorproof.type_checking_input_glue_sound.
Print Assumptions Generatorproof.type_checking_input_glue_generated.
Print Assumptions Generatorproof.type_checking_output_glue_generated.
Print Assumptions Generatorproof.generate_valid_assignments.
Print Assumptions Generatorproof.loop_input_glue_then_step.
Print Assumptions Generatorproof.generate_inputs_written_only_by_input_glue.
Print Assumptions Generatorproof.generate_outputs_not_written.
Print Assumptions Generatorproof.generate_inputs_address_not_taken.
(* Shape of the generated program, for T1/T2. *)
Print Assumptions Generatorproof.generate_names_distinct.
Print Assumptions Generatorproof.generate_locals_fresh.
Print Assumptions Generatorproof.generate_callback.
Print Assumptions Generatorproof.generate_input_glue.
Print Assumptions Generatorproof.generate_output_glue.
Print Assumptions Generatorproof.generate_loop.
Print Assumptions Generatorproof.generate_main.
Print Assumptions Generatorproof.generate_externals.
Print Assumptions Generatorproof.generate_topic_externals.
Print Assumptions Generatorproof.generate_assigned_places.
Print Assumptions Generatorproof.generate_addresses_taken.
From ROSGen Require Glueproof Loopproof.
(* T1 (paper Figs. 10, 12, for every model): the generated callbacks,
   input_glue and output glue meet their data delivery specifications. *)
Print Assumptions Glueproof.generate_callback_ddc.
Print Assumptions Glueproof.generate_input_glue_ddc.
Print Assumptions Glueproof.generate_output_glue_ddc.
(* T2: data delivery correctness of every generated node, over whole runs. *)
Print Assumptions Loopproof.generate_node_ddc.
