(** * Controller arrays (issue 15): a whole scan into [Scan[4]], back out of [Cmd[4]] *)

(** An echo node in the style of Embedded Coder: the controller's inputs
    are an array [real32_T Scan[4]] and a [uint32] [Len], its outputs an
    array [real32_T Cmd[4]] and a [uint32] [NC].  [/scan] carries
    [ranges] as a bounded sequence of at most 4 [float32]
    ([ros_seq_float32_4]); one input relation per element feeds
    [Scan[i]] from [ranges.data[i]] (what the front end expands
    [{field: ranges, input: Scan}] into), and [Len] the received length.
    The output relations write [Cmd[i]] into [data.data[i]] and [NC]
    into [data.len] of the message published on [/out].  The controller
    echoes: [Cmd = Scan], [NC = Len].

    Six scans arrive, of lengths 0, 1, 3, 4, 5 and 8 (0, 1, N-1, N, N+1
    and 2N), each with junk past its length: the interpreter gives the
    controller the first [min(len, 4)] elements and zeros after (the
    padding of [Environment.clamp]), and publishes them back.  Four
    generator mutants are refuted against T2: two elements' destinations
    swapped, the copy of the last element dropped (the padding of a
    short scan hides it, a full one does not), an output element read
    one index off, and the length written into the wrong field of the
    published sequence.  The well-formedness rules refuse an element fed
    twice or not at all, an index past the array, an element of another
    type, a fallback or a derived input into an array. *)

From Coq Require Import String List ZArith Lia.
From Flocq Require Import IEEE754.Binary IEEE754.Bits.
From ROSGen Require Import FloatBits Errors Syntax Values Memory Environment Semantics Interp Interpproof
  NodeModel Wellformed Generator Generatorspec DDC Loopproof.
From ROSGenTests Require Import LandShark Mutants Sequences GeneratorExamples.
Import ListNotations.
(* The interpreter's fuel, 6000, is a large [nat]: its numeral is read as
   [Nat.of_num_uint] applied to its digits, as intended. *)
Local Set Warnings "-abstract-large-number".
Local Open Scope string_scope.
Local Open Scope list_scope.

(** ** The model *)

Definition relem (i : Z) : path := [PField "ranges"; PField "data"; PIndex i].

Definition echo : node_model := {|
  nm_name := "echo"; nm_period_ms := 20; nm_ctrl := "Controller";
  nm_in_var := "Controller_U"; nm_in_struct := "ExtU_Controller_T";
  nm_inputs := [("Scan", FTarray (FTprim Pfloat32) 4); ("Len", FTprim Puint32)];
  nm_out_var := "Controller_Y"; nm_out_struct := "ExtY_Controller_T";
  nm_outputs := [("Cmd", FTarray (FTprim Pfloat32) 4); ("NC", FTprim Puint32)];
  nm_msgs := [seq4; laser_scan; floats_msg];
  nm_topics := [scan; out];
  nm_inrels := map (fun i => mkinrel_at "scan" (relem i) "Scan" [PIndex i]) [0; 1; 2; 3]%Z
               ++ [mkinrel "scan" (ranges "len") "Len"];
  nm_outrels := mkoutrel "NC" "out" dlen
                :: map (fun i => mkoutrel_at "Cmd" [PIndex i] "out" (delem i)) [0; 1; 2; 3]%Z;
  nm_timeouts := []; nm_fallbacks := []; nm_drels := []; nm_stamps := []; nm_stamp_from := [];
  nm_strings := [] |}.

Example echo_wf: wf echo = true.
Proof. vm_compute. reflexivity. Qed.

Definition echo_result : res program := Eval vm_compute in generate echo.
Definition echo_prog : program :=
  Eval vm_compute in match echo_result with OK p => p | Error _ => mkprogram [] [] "" end.

Lemma echo_generates: generate echo = OK echo_prog.
Proof. vm_compute. reflexivity. Qed.

(** The controller's inputs struct has the array member, as Embedded
    Coder declares it: [float Scan[4]; unsigned int Len;]. *)
Example echo_inputs_struct:
  find_composite "ExtU_Controller_T" (prog_types echo_prog)
  = Some (Composite "ExtU_Controller_T" [("Scan", Tarray (Tfloat F32) 4); ("Len", Tint I32 Unsigned)]).
Proof. vm_compute. reflexivity. Qed.

(** ** The echo controller *)

Definition echo_y (u : mval) : mval :=
  MVstruct [("Cmd", match mval_get u [Sfield "Scan"] with Some a => a | None => MVarray [] end);
            ("NC", match mval_get u [Sfield "Len"] with Some l => l | None => MVscalar (Vint 0) end)].

Definition ectx : ros_context unit :=
  mkctx (fun k => match nth_error scans k with
                  | Some (l, xs) => [mkarrival "/scan" (scan_msg l xs) 0]
                  | None => []
                  end)
        (fun _ => 0%Z) tt (fun _ u => (tt, echo_y u)) Ros1.

Lemma ectx_arrivals_wt: arrivals_wt echo ectx.
Proof.
  intros k a tp H Htp _. apply mval_typecheck_iff.
  simpl in Htp. destruct Htp as [<-|[]].
  simpl in H. do 6 (destruct k as [|k]; [simpl in H; destruct H as [<-|[]]; vm_compute; reflexivity|]).
  simpl in H. destruct k; contradiction.
Qed.

(** The echo is well typed on inputs of their type; on anything else the
    outputs are checked by the environment ([controller_wt] asks for
    every input value, so the check is on the typed ones below). *)
Definition ectx_typed : ros_context unit :=
  mkctx (ctx_arrivals ectx) (ctx_time ectx) tt
        (fun _ u => (tt, let y := echo_y u in
                         if mval_typecheck (composites echo) (Tstruct "ExtY_Controller_T") y then y
                         else MVstruct [("Cmd", MVarray (repeat (MVscalar (Vsingle (f32 0))) 4));
                                        ("NC", MVscalar (Vint 0))])) Ros1.

Lemma ectx_controller_wt: controller_wt echo ectx_typed.
Proof.
  intros s u. unfold ectx_typed. cbn [ctx_step snd].
  destruct (mval_typecheck (composites echo) (Tstruct "ExtY_Controller_T") (echo_y u)) eqn:T;
    apply mval_typecheck_iff; [exact T|vm_compute; reflexivity].
Qed.

Lemma ectx_typed_arrivals_wt: arrivals_wt echo ectx_typed.
Proof. exact ectx_arrivals_wt. Qed.

(** ** What the controller receives and what is published *)

Definition f32_bits (mv : option mval) : option Z :=
  match mv with Some (MVscalar (Vsingle x)) => Some (bits_of_b32 x) | Some (MVscalar (Vint n)) => Some n | _ => None end.

(** The four elements of [Scan] and [Len] of each step's inputs. *)
Definition scans_of (t : trace) : list (list (option Z)) :=
  flat_map (fun e => match e with
                     | Estep u _ => [map (fun i => f32_bits (mval_get u [Sfield "Scan"; Sindex i])) [0; 1; 2; 3]%Z
                                     ++ [f32_bits (mval_get u [Sfield "Len"])]]
                     | _ => []
                     end) t.

(** The length and the four elements of each published message. *)
Definition echoes_of (t : trace) : list (list (option Z)) :=
  flat_map (fun e => match e with
                     | Epublish _ mv => [map (bits_at mv) (dlen :: map delem [0; 1; 2; 3]%Z)]
                     | _ => []
                     end) t.

(** The controller sees the first [min(len, 4)] elements, zeros after
    (never the junk), and the capped length; the same goes out. *)
Example echo_run:
  match run_trace 6000%nat echo_prog ectx_typed 6 with
  | Some t =>
      scans_of t =
        map (map Some)
        [[0; 0; 0; 0; 0]; [0x40A00000; 0; 0; 0; 1]; [0x40A00000; 0x40C00000; 0x40E00000; 0; 3];
         [0x40A00000; 0x40C00000; 0x40E00000; 0x41000000; 4];
         [0x40A00000; 0x40C00000; 0x40E00000; 0x41000000; 4];
         [0x40A00000; 0x40C00000; 0x40E00000; 0x41000000; 4]]%Z
      /\ echoes_of t =
        map (map Some)
        [[0; 0; 0; 0; 0]; [1; 0x40A00000; 0; 0; 0]; [3; 0x40A00000; 0x40C00000; 0x40E00000; 0];
         [4; 0x40A00000; 0x40C00000; 0x40E00000; 0x41000000];
         [4; 0x40A00000; 0x40C00000; 0x40E00000; 0x41000000];
         [4; 0x40A00000; 0x40C00000; 0x40E00000; 0x41000000]]%Z
  | None => False
  end.
Proof. vm_compute. split; reflexivity. Qed.

(** ** Mutants *)

(** A mutant [p] whose [n]-cycle run fails a check [ok] that T2 implies
    does not satisfy T2. *)
Definition echeck_with (ok : nat -> trace -> bool) (p : program) (n : nat) : bool :=
  match run_trace 6000%nat p ectx_typed n with
  | Some t => ok n t
  | None => true
  end.

Lemma erefute_with:
  forall ok, (forall n t, run_ok echo ectx_typed n t -> ok n t = true) ->
  forall p n, echeck_with ok p n = false -> ~ node_ddc echo p.
Proof.
  intros ok OK p n H D. unfold echeck_with in H.
  destruct (run_trace 6000%nat p ectx_typed n) as [t|] eqn:R; [|discriminate].
  destruct (D unit ectx_typed n ectx_typed_arrivals_wt ectx_controller_wt) as [_ All].
  rewrite (OK n t (All t (run_trace_sound _ ectx_typed 6000%nat p n t R))) in H. discriminate.
Qed.

(** The inputs ([Mutants.run_okb]). *)
Definition echeck := echeck_with (run_okb echo ectx_typed).

Lemma erefute: forall p n, echeck p n = false -> ~ node_ddc echo p.
Proof. apply erefute_with. intros n t R. apply (run_ok_okb _ _ _ _ _ R). Qed.

(** The generated program passes (as T2 says it must). *)
Example echo_passes: echeck echo_prog 6 = true.
Proof. vm_compute. reflexivity. Qed.

(** The assignments of a statement changed by [h]. *)
Fixpoint map_assigns (h : expr -> expr) (s : statement) : statement :=
  match s with
  | Ssequence a b => Ssequence (map_assigns h a) (map_assigns h b)
  | Sassign l e => Sassign (h l) e
  | _ => s
  end.

(** (c1) the destinations of elements 1 and 2 swapped: [Scan[2] = ranges.data[1]] *)
Definition swap12 (e : expr) : expr :=
  match e with
  | Eindex a (Econst_int 1 ti) t => Eindex a (Econst_int 2 ti) t
  | Eindex a (Econst_int 2 ti) t => Eindex a (Econst_int 1 ti) t
  | _ => e
  end.
Definition m_swapped : program := on_function "scan_callback" (map_assigns swap12) echo_prog.
Theorem m_swapped_refuted: ~ node_ddc echo m_swapped.
Proof. apply (erefute _ 3). vm_compute. reflexivity. Qed.

(** (c2) the copy of the last element dropped: a scan of length 4 leaves
    [Scan[3]] at 0 (a shorter one would not show it) *)
Fixpoint drop_last_copy (s : statement) : statement :=
  match s with
  | Ssequence (Ssequence (Sset x e) (Sassign (Eindex a (Econst_int 3 ti) t) r)) rest => drop_last_copy rest
  | Ssequence a b => Ssequence (drop_last_copy a) (drop_last_copy b)
  | _ => s
  end.
Definition m_no_last : program := on_function "scan_callback" drop_last_copy echo_prog.
Theorem m_no_last_refuted: ~ node_ddc echo m_no_last.
Proof. apply (erefute _ 4). vm_compute. reflexivity. Qed.

(** (c5) the element relations copied by [input_glue] as well, from the
    topic's global (a generator that made them direct, rule 4.16, in the
    callback but forgot to leave them out of [input_glue]): the global
    no longer holds the elements, so [input_glue] overwrites what the
    callback wrote with zeros. *)
Definition both_copy_body : statement :=
  seq_of (map (input_copy echo (make_tables echo)) (nm_inrels echo)).
Definition m_glue_copies_too : program :=
  mkprogram (prog_types echo_prog)
    (map (fun d : ident * globdef =>
            if string_dec (fst d) "input_glue"
            then (fst d, Gfun (Internal (mkfunction Tvoid [] []
                                           (temps_of (map (inrel_prim (make_tables echo)) (nm_inrels echo)))
                                           both_copy_body)))
            else d) (prog_defs echo_prog))
    (prog_main echo_prog).
Theorem m_glue_copies_too_refuted: ~ node_ddc echo m_glue_copies_too.
Proof. apply (erefute _ 2). vm_compute. reflexivity. Qed.

(** *** The published array *)

(** A computable consequence of T2 for the echo: in every cycle the
    message published for the outputs [y] is sent with the length
    [min(NC, 4)] and, when that length is not 0, element 0 equal to
    [Cmd[0]] (by [published_value] and [Main.sent_sequence]). *)
Definition echo_sent_okb : mval -> mval -> bool := seq_sent_okb [Sfield "NC"] [Sfield "Cmd"; Sindex 0].

Lemma echo_cycle_sent:
  forall y now g mv,
  mval_has_type (composites echo) (Tstruct (nm_out_struct echo)) y ->
  published_value echo y now g out mv -> echo_sent_okb y (sent echo out mv) = true.
Proof.
  intros y now g mv Ty P.
  exact (seq_sent echo out (mkoutrel "NC" "out" dlen) (mkoutrel_at "Cmd" [PIndex 0] "out" (delem 0)) y now g mv
           (or_introl eq_refl) eq_refl eq_refl ltac:(simpl; auto) eq_refl eq_refl
           ltac:(vm_compute; reflexivity) ltac:(vm_compute; reflexivity)
           ltac:(repeat split; vm_compute; reflexivity) Ty P).
Qed.

Lemma run_ok_echo: forall n t, run_ok echo ectx_typed n t -> pub_okb echo_sent_okb t = true.
Proof.
  intros n t R. apply (run_ok_pub unit echo ectx_typed out echo_sent_okb n t eq_refl ectx_controller_wt); auto.
  intros y now g mv Ty P. apply (echo_cycle_sent y now g mv Ty P).
Qed.

(** The published array. *)
Definition echeck_out := echeck_with (fun _ => pub_okb echo_sent_okb).

Lemma erefute_out: forall p n, echeck_out p n = false -> ~ node_ddc echo p.
Proof. apply erefute_with. intros n t R. apply (run_ok_echo n t R). Qed.

Example echo_passes_out: echeck_out echo_prog 6 = true.
Proof. vm_compute. reflexivity. Qed.

(** (c3) an output element read one index off: [data.data[0] = Cmd[1]] *)
Definition shift_src (e : expr) : expr :=
  match e with
  | Eindex a (Econst_int 0 ti) t => Eindex a (Econst_int 1 ti) t
  | _ => e
  end.
Fixpoint map_sets (h : expr -> expr) (s : statement) : statement :=
  match s with
  | Ssequence a b => Ssequence (map_sets h a) (map_sets h b)
  | Sset x e => Sset x (h e)
  | _ => s
  end.
Definition m_out_off : program := on_function "output_glue_out" (map_sets shift_src) echo_prog.
Theorem m_out_off_refuted: ~ node_ddc echo m_out_off.
Proof. apply (erefute_out _ 3). vm_compute. reflexivity. Qed.

(** (c4) the length written into the wrong field of the sequence:
    [data.truncated = NC] instead of [data.len] (the length stays 0) *)
Definition len_to_trunc (e : expr) : expr :=
  match e with
  | Efield a "len" t => Efield a "truncated" (Tint I8 Unsigned)
  | _ => e
  end.
Definition m_len_field : program := on_function "output_glue_out" (map_assigns len_to_trunc) echo_prog.
Theorem m_len_field_refuted: ~ node_ddc echo m_len_field.
Proof. apply (erefute_out _ 2). vm_compute. reflexivity. Qed.

(** ** Refused models *)

Definition with_inputs_rels (m : node_model) (ins : list (ident * ftype)) (l : list inrel) : node_model :=
  {| nm_name := nm_name m; nm_period_ms := nm_period_ms m; nm_ctrl := nm_ctrl m;
     nm_in_var := nm_in_var m; nm_in_struct := nm_in_struct m; nm_inputs := ins;
     nm_out_var := nm_out_var m; nm_out_struct := nm_out_struct m; nm_outputs := nm_outputs m;
     nm_msgs := nm_msgs m; nm_topics := nm_topics m; nm_inrels := l; nm_outrels := nm_outrels m;
     nm_timeouts := nm_timeouts m; nm_fallbacks := nm_fallbacks m; nm_drels := nm_drels m;
     nm_stamps := []; nm_stamp_from := []; nm_strings := [] |}.

(** An element not fed: [Scan[3]]. *)
Example refuse_unfed:
  refused (with_inrels echo (removelast (removelast (nm_inrels echo)) ++ [mkinrel "scan" (ranges "len") "Len"]))
    "Generator: controller input not fed by any input relation: 'Scan[3]'".
Proof. vm_compute. split; reflexivity. Qed.

(** An element fed twice: [Scan[0]] from elements 0 and 1. *)
Example refuse_twice:
  refused (with_inrels echo (nm_inrels echo ++ [mkinrel_at "scan" (relem 1) "Scan" [PIndex 0]]))
    "Generator: controller input fed by several input relations: 'Scan[0]'".
Proof. vm_compute. split; reflexivity. Qed.

(** An index past the array: [Scan[4]]. *)
Example refuse_past:
  refused (with_inrels echo (nm_inrels echo ++ [mkinrel_at "scan" (relem 3) "Scan" [PIndex 4]]))
    "Generator: input relation: 'Scan[4]' is not a scalar leaf of the controller's inputs".
Proof. vm_compute. split; reflexivity. Qed.

(** An array of another element type: [double Scan[4]] fed by [float]s. *)
Example refuse_type:
  refused (with_inputs_rels echo [("Scan", FTarray (FTprim Pfloat64) 4); ("Len", FTprim Puint32)] (nm_inrels echo))
    "Generator: type mismatch in input relation: 'scan.ranges.data[0]' is float32 but controller input 'Scan[0]' is float64".
Proof. vm_compute. split; reflexivity. Qed.

(** An array input related as a whole (no element path). *)
Example refuse_whole:
  wf (with_inrels echo (mkinrel "scan" (relem 0) "Scan" :: nm_inrels echo)) = false.
Proof. vm_compute. reflexivity. Qed.

(** A two-dimensional controller array. *)
Example refuse_2d:
  wf (with_inputs_rels echo [("Scan", FTarray (FTarray (FTprim Pfloat32) 4) 1); ("Len", FTprim Puint32)]
        (nm_inrels echo)) = false.
Proof. vm_compute. reflexivity. Qed.
