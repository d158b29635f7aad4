(** * Bounded sequences (issue 15): the environment's conversion, a run, and mutants *)

(** A scanner node: it subscribes to [/scan], whose [sensor_msgs/LaserScan]
    message carries [ranges] as a bounded sequence of at most 4 [float32]
    ([ros_seq_float32_4]), and feeds the controller [ranges[1]], the
    received length and whether the scan was truncated, through ordinary
    input relations on the leaves [ranges.data[1]], [ranges.len] and
    [ranges.truncated] (the element relation is direct, rule 4.16: the
    callback writes it into [Controller_U]; [input_glue] copies the
    other two from the topic's global).  Six scans arrive, of lengths 0, 1, 3, 4, 5 and 8
    (0, 1, N-1, N, N+1 and 2N), each carrying junk past its length; the
    interpreter gives the controller, cycle by cycle, what
    [Environment.clamp] says: the element when the scan has it and 0
    otherwise, the length capped at 4, truncated exactly for 5 and 8.
    Two generator mutants are refuted against T2: the element read one
    index off, and the length input given the maximum instead of the
    received length. *)

From Coq Require Import String List ZArith Lia.
From Flocq Require Import IEEE754.Binary IEEE754.Bits.
From ROSGen Require Import FloatBits Errors Syntax Values Memory Environment Semantics Interp Interpproof
  NodeModel Wellformed Generator Generatorspec DDC Loopproof.
From ROSGenTests Require Import LandShark Mutants.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope list_scope.

(** ** The model *)

Definition seq4 : msgdef :=
  mkmsgdef "ros_seq_float32_4" [("len", FTprim Puint32); ("truncated", FTprim Pbool);
                                ("data", FTarray (FTprim Pfloat32) 4)].
Definition laser_scan : msgdef :=
  mkmsgdef "sensor_msgs_LaserScan" [("angle_min", FTprim Pfloat32); ("ranges", FTmsg "ros_seq_float32_4")].

Definition scan : topic := mktopic "/scan" "scan" "sensor_msgs/LaserScan" Subscribe "sensor_msgs_LaserScan" 1.
Definition cmd : topic := mktopic "/cmd" "cmd" "geometry_msgs/Twist" Publish "geometry_msgs_Twist" 1.

Definition ranges (s : string) : path := [PField "ranges"; PField s].
Definition range1 : path := [PField "ranges"; PField "data"; PIndex 1].

Definition scanner : node_model := {|
  nm_name := "scanner"; nm_period_ms := 20; nm_ctrl := "Controller";
  nm_in_var := "Controller_U"; nm_in_struct := "ExtU_Controller_T";
  nm_inputs := [("R1", FTprim Pfloat32); ("Len", FTprim Puint32); ("Trunc", FTprim Pbool)];
  nm_out_var := "Controller_Y"; nm_out_struct := "ExtY_Controller_T";
  nm_outputs := [("Out1", FTprim Pfloat64)];
  nm_msgs := [seq4; laser_scan; geometry_msgs_Vector3; geometry_msgs_Twist];
  nm_topics := [scan; cmd];
  nm_inrels := [mkinrel "scan" range1 "R1"; mkinrel "scan" (ranges "len") "Len";
                mkinrel "scan" (ranges "truncated") "Trunc"];
  nm_outrels := [mkoutrel "Out1" "cmd" [PField "linear"; PField "x"]];
  nm_timeouts := []; nm_fallbacks := []; nm_drels := []; nm_stamps := []; nm_stamp_from := [];
  nm_strings := [] |}.

Example scanner_wf: wf scanner = true.
Proof. vm_compute. reflexivity. Qed.

Definition scanner_result : res program := Eval vm_compute in generate scanner.
Definition scanner_prog : program :=
  Eval vm_compute in match scanner_result with OK p => p | Error _ => mkprogram [] [] "" end.

Lemma scanner_generates: generate scanner = OK scanner_prog.
Proof. vm_compute. reflexivity. Qed.

(** ** Scans as they are sent *)

Definition f32 (bits : Z) : float32 := float32_of_bits bits.
Definition r5 : float32 := f32 0x40A00000.   (**r 5.0 *)
Definition r6 : float32 := f32 0x40C00000.   (**r 6.0 *)
Definition r7 : float32 := f32 0x40E00000.   (**r 7.0 *)
Definition r8 : float32 := f32 0x41000000.   (**r 8.0 *)
Definition junk : float32 := f32 0x41100000. (**r 9.0, past the length *)

Definition sce : composite_env := composites scanner.

(** A scan of length [l] whose first four elements are [xs] (the
    elements past 4 are not represented: no node can see them). *)
Definition scan_msg (l : Z) (xs : list float32) : mval :=
  MVstruct [("angle_min", MVscalar (Vsingle (f32 0)));
            ("ranges", MVstruct [("len", MVscalar (Vint l)); ("truncated", MVscalar (Vint 0));
                                 ("data", MVarray (map (fun x => MVscalar (Vsingle x)) xs))])].

Definition scans : list (Z * list float32) :=
  [(0, [junk; junk; junk; junk]);   (* length 0 *)
   (1, [r5; junk; junk; junk]);     (* 1 *)
   (3, [r5; r6; r7; junk]);         (* N - 1 *)
   (4, [r5; r6; r7; r8]);           (* N *)
   (5, [r5; r6; r7; r8]);           (* N + 1 *)
   (8, [r5; r6; r7; r8])]%Z.        (* 2 N *)

Definition y_out : mval := MVstruct [("Out1", MVscalar (Vfloat (float64_of_bits 0)))].

Definition sctx : ros_context unit :=
  mkctx (fun k => match nth_error scans k with
                  | Some (l, xs) => [mkarrival "/scan" (scan_msg l xs) 0]
                  | None => []
                  end)
        (fun _ => 0%Z) tt (fun _ _ => (tt, y_out)) Ros1.

Lemma sctx_arrivals_wt: arrivals_wt scanner sctx.
Proof.
  intros k a tp H Htp _. apply mval_typecheck_iff.
  simpl in Htp. destruct Htp as [<-|[]].
  simpl in H. do 6 (destruct k as [|k]; [simpl in H; destruct H as [<-|[]]; vm_compute; reflexivity|]).
  simpl in H. destruct k; contradiction.
Qed.

Lemma sctx_controller_wt: controller_wt scanner sctx.
Proof. intros s u. apply mval_typecheck_iff. vm_compute. reflexivity. Qed.

(** ** What the controller receives *)

(** The inputs of each step of a trace: [R1] (its bits), [Len], [Trunc]. *)
Definition inputs_of (t : trace) : list (option Z * option Z * option Z) :=
  flat_map (fun e => match e with
                     | Estep u _ =>
                         [(match mval_get u [Sfield "R1"] with Some (MVscalar (Vsingle x)) => Some (bits_of_b32 x) | _ => None end,
                           match mval_get u [Sfield "Len"] with Some (MVscalar (Vint n)) => Some n | _ => None end,
                           match mval_get u [Sfield "Trunc"] with Some (MVscalar (Vint n)) => Some n | _ => None end)]
                     | _ => []
                     end) t.

(** [ranges[1]] is 0 for the scans of length 0 and 1 (the junk is not
    seen), 6.0 otherwise; the length is capped at 4; truncated for 5 and
    8 only. *)
Example scanner_run:
  match run_trace 4000 scanner_prog sctx 6 with
  | Some t => inputs_of t =
      [(Some 0, Some 0, Some 0); (Some 0, Some 1, Some 0); (Some 0x40C00000, Some 3, Some 0);
       (Some 0x40C00000, Some 4, Some 0); (Some 0x40C00000, Some 4, Some 1); (Some 0x40C00000, Some 4, Some 1)]%Z
  | None => False
  end.
Proof. vm_compute. reflexivity. Qed.

(** ** Mutants *)

Definition scheck : program -> nat -> bool := check_in scanner sctx 4000.

Lemma srefute: forall p n, scheck p n = false -> ~ node_ddc scanner p.
Proof. exact (refute_in scanner sctx 4000 sctx_arrivals_wt sctx_controller_wt). Qed.

(** The generated program passes (as T2 says it must). *)
Example scanner_passes: scheck scanner_prog 6 = true.
Proof. vm_compute. reflexivity. Qed.

(** The body of the function [fname] changed by [g]. *)
Definition on_function (fname : ident) (g : statement -> statement) (p : program) : program :=
  mkprogram (prog_types p)
    (map (fun d : ident * globdef => if string_dec (fst d) fname
                   then match snd d with
                        | Gfun (Internal f) =>
                            (fst d, Gfun (Internal (mkfunction (fn_return f) (fn_params f) (fn_vars f)
                                                                (fn_temps f) (g (fn_body f)))))
                        | _ => d
                        end
                   else d) (prog_defs p))
    (prog_main p).

(** The body of [input_glue] changed by [g]. *)
Definition on_input_glue : (statement -> statement) -> program -> program := on_function "input_glue".

Fixpoint map_exprs (h : expr -> expr) (s : statement) : statement :=
  match s with
  | Ssequence a b => Ssequence (map_exprs h a) (map_exprs h b)
  | Sset x e => Sset x (h e)
  | Sassign l e => Sassign l (h e)
  | _ => s
  end.

(** (q1) the element read one index off: [ranges.data[2]] for
    [ranges.data[1]], in the callback, which copies the element relation
    straight into [Controller_U] (rule 4.16: an array element of a topic
    that is not timed) *)
Definition shift_index (e : expr) : expr :=
  match e with
  | Eindex a (Econst_int 1 ti) t => Eindex a (Econst_int 2 ti) t
  | _ => e
  end.
Definition m_index_off : program := on_function "scan_callback" (map_exprs shift_index) scanner_prog.
Theorem m_index_off_refuted: ~ node_ddc scanner m_index_off.
Proof. apply (srefute _ 3). vm_compute. reflexivity. Qed.

(** (q2) the length input given the maximum, 4, instead of the length *)
Definition max_len (e : expr) : expr :=
  match e with
  | Efield a "len" t => Econst_int 4 t
  | _ => e
  end.
Definition m_max_length : program := on_input_glue (map_exprs max_len) scanner_prog.
Theorem m_max_length_refuted: ~ node_ddc scanner m_max_length.
Proof. apply (srefute _ 1). vm_compute. reflexivity. Qed.

(** [Main.converted_sequence] applies to the scanner's [ranges]: the path
    reaches the bounded sequence through no other one ([bounded_at]). *)
Example ranges_bounded_at: bounded_at scanner scan [PField "ranges"] "ros_seq_float32_4" 4 (Tfloat F32).
Proof. repeat split; vm_compute; reflexivity. Qed.

(** ** Publishing a bounded sequence from the controller *)

(** A publisher node: the controller's outputs [L] ([uint32]), [E0] and
    [E2] ([float32]) feed the length and the elements 0 and 2 of the
    [data] sequence (at most 4 [float32]) of the message it publishes on
    [/out]; its one input is the length of the scans on [/scan], on
    which nothing arrives.  The controller outputs, cycle after cycle, the
    lengths 0, 1, 3, 4, 5 and 8 (0, 1, N-1, N, N+1, 2N) with [E0 = 5.0]
    and [E2 = 7.0]. *)
Definition floats_msg : msgdef := mkmsgdef "std_msgs_Floats" [("data", FTmsg "ros_seq_float32_4")].
Definition out : topic := mktopic "/out" "out" "std_msgs/Floats" Publish "std_msgs_Floats" 1.
Definition dlen : path := [PField "data"; PField "len"].
Definition delem (j : Z) : path := [PField "data"; PField "data"; PIndex j].

Definition publisher : node_model := {|
  nm_name := "publisher"; nm_period_ms := 20; nm_ctrl := "Controller";
  nm_in_var := "Controller_U"; nm_in_struct := "ExtU_Controller_T";
  nm_inputs := [("Len", FTprim Puint32)];
  nm_out_var := "Controller_Y"; nm_out_struct := "ExtY_Controller_T";
  nm_outputs := [("L", FTprim Puint32); ("E0", FTprim Pfloat32); ("E2", FTprim Pfloat32)];
  nm_msgs := [seq4; laser_scan; floats_msg];
  nm_topics := [scan; out];
  nm_inrels := [mkinrel "scan" (ranges "len") "Len"]; nm_outrels := [mkoutrel "L" "out" dlen; mkoutrel "E0" "out" (delem 0);
                                  mkoutrel "E2" "out" (delem 2)];
  nm_timeouts := []; nm_fallbacks := []; nm_drels := []; nm_stamps := []; nm_stamp_from := [];
  nm_strings := [] |}.

Example publisher_wf: wf publisher = true.
Proof. vm_compute. reflexivity. Qed.

Definition publisher_result : res program := Eval vm_compute in generate publisher.
Definition publisher_prog : program :=
  Eval vm_compute in match publisher_result with OK p => p | Error _ => mkprogram [] [] "" end.

Lemma publisher_generates: generate publisher = OK publisher_prog.
Proof. vm_compute. reflexivity. Qed.

Definition lengths : list Z := [0; 1; 3; 4; 5; 8]%Z.

Definition y_of (k : nat) : mval :=
  MVstruct [("L", MVscalar (Vint (nth k lengths 0%Z))); ("E0", MVscalar (Vsingle r5));
            ("E2", MVscalar (Vsingle r7))].

Definition pctx : ros_context nat :=
  mkctx (fun _ => []) (fun _ => 0%Z) O (fun k _ => (S k, y_of k)) Ros1.

Lemma pctx_arrivals_wt: arrivals_wt publisher pctx.
Proof. intros k a tp H. contradiction. Qed.


Lemma pctx_controller_wt: controller_wt publisher pctx.
Proof.
  intros s u. change (snd (ctx_step pctx s u)) with (y_of s). apply mval_typecheck_iff. unfold y_of.
  destruct (nth_in_or_default s lengths 0%Z) as [H|H]; [|rewrite H; vm_compute; reflexivity].
  destruct H as [<-|[<-|[<-|[<-|[<-|[<-|[]]]]]]]; vm_compute; reflexivity.
Qed.

(** What is sent of each published message: its length, whether it was
    truncated, and the bits of its four elements. *)
Definition bits_at (mv : mval) (p : path) : option Z :=
  match mval_get mv (path_steps p) with
  | Some (MVscalar (Vsingle x)) => Some (bits_of_b32 x)
  | Some (MVscalar (Vint n)) => Some n
  | _ => None
  end.

Definition sent_of (t : trace) : list (list (option Z)) :=
  flat_map (fun e => match e with
                     | Epublish _ mv => [map (bits_at mv) (dlen :: [PField "data"; PField "truncated"]
                                                            :: map delem [0; 1; 2; 3]%Z)]
                     | _ => []
                     end) t.

(** The lengths are capped at 4, [truncated] set for 5 and 8; the
    elements past the length are not sent (zero), element 1 and 3 are
    zero (no output feeds them). *)
Example publisher_run:
  match run_trace 4000 publisher_prog pctx 6 with
  | Some t => sent_of t =
      map (map Some)
      [[0; 0; 0; 0; 0; 0]; [1; 0; 0x40A00000; 0; 0; 0]; [3; 0; 0x40A00000; 0; 0x40E00000; 0];
       [4; 0; 0x40A00000; 0; 0x40E00000; 0]; [4; 1; 0x40A00000; 0; 0x40E00000; 0];
       [4; 1; 0x40A00000; 0; 0x40E00000; 0]]%Z
  | None => False
  end.
Proof. vm_compute. reflexivity. Qed.

(** A computable consequence of T2 for this node: in every cycle, the
    published message that the step's outputs [y] call for is sent with
    the length [min(L, 4)] and, when that length is not 0, element 0
    equal to [E0] (by [published_value] and [Main.sent_sequence]). *)
Definition seq_sent_okb (yl ye : Values.path) (y mv : mval) : bool :=
  match mval_get y yl, mval_get y ye with
  | Some (MVscalar (Vint l)), Some (MVscalar (Vsingle e0)) =>
      match bits_at mv dlen, bits_at mv (delem 0) with
      | Some n, Some b0 =>
          Z.eqb n (Z.min l 4) && (if (0 <? Z.min l 4)%Z then Z.eqb b0 (bits_of_b32 e0) else true)
      | _, _ => false
      end
  | _, _ => false
  end.

(** For any node that publishes, on a topic [tp], a [ros_seq_float32_4]
    at [data] whose length comes from the output leaf of [ol] and whose
    element 0 from that of [oe]: every message [published_value] allows
    is sent with that length capped and that element 0. *)
Lemma seq_sent:
  forall m tp ol oe y now g mv,
  In ol (nm_outrels m) -> or_topic ol = tp_cname tp -> or_path ol = dlen ->
  In oe (nm_outrels m) -> or_topic oe = tp_cname tp -> or_path oe = delem 0 ->
  type_at (composites m) (Tstruct (nm_out_struct m)) (Sfield (or_output ol) :: path_steps (or_elem ol))
    = Some (Tint I32 Unsigned) ->
  type_at (composites m) (Tstruct (nm_out_struct m)) (Sfield (or_output oe) :: path_steps (or_elem oe))
    = Some (Tfloat F32) ->
  bounded_at m tp [PField "data"] "ros_seq_float32_4" 4 (Tfloat F32) ->
  mval_has_type (composites m) (Tstruct (nm_out_struct m)) y ->
  published_value m y now g tp mv ->
  seq_sent_okb (Sfield (or_output ol) :: path_steps (or_elem ol)) (Sfield (or_output oe) :: path_steps (or_elem oe))
               y (sent m tp mv) = true.
Proof.
  intros m tp ol oe y now g mv Hl El Pl He Ee Pe TL TE B Ty (T & Rel & _).
  destruct (Rel ol Hl El) as (vl & Gl & Ml). destruct (Rel oe He Ee) as (v0 & G0 & M0).
  rewrite Pl in Ml. rewrite Pe in M0.
  destruct (mval_get_has_type _ _ _ _ _ Ty TL) as (xl & Gxl & Txl). rewrite Gl in Gxl. inversion Gxl; subst xl.
  inversion Txl as [? ? _ Vl| |]; subst.
  assert (Ex: exists l, vl = Vint l) by (destruct vl; try contradiction; eauto). destruct Ex as [l ->].
  destruct (mval_get_has_type _ _ _ _ _ Ty TE) as (x0 & Gx0 & Tx0). rewrite G0 in Gx0. inversion Gx0; subst x0.
  inversion Tx0 as [? ? _ V0| |]; subst.
  assert (Ex: exists e0, v0 = Vsingle e0) by (destruct v0; try contradiction; eauto). destruct Ex as [e0 ->].
  destruct (sent_sequence m tp mv [PField "data"] "ros_seq_float32_4" 4 (Tfloat F32) l T B Ml) as (L & _ & D).
  unfold seq_sent_okb. rewrite Gl, G0. unfold bits_at.
  change (path_steps dlen) with (path_steps ([PField "data"] ++ [PField "len"])). rewrite L.
  change (path_steps (delem 0)) with (path_steps ([PField "data"] ++ [PField "data"; PIndex 0])).
  rewrite (D 0%Z ltac:(lia)).
  rewrite Z.eqb_refl. simpl andb.
  destruct (0 <? Z.min l 4)%Z; [|reflexivity].
  change (path_steps ([PField "data"] ++ [PField "data"; PIndex 0])) with (path_steps (delem 0)).
  rewrite M0. apply Z.eqb_refl.
Qed.

Definition cycle_sent_okb : mval -> mval -> bool := seq_sent_okb [Sfield "L"] [Sfield "E0"].

Lemma cycle_sent:
  forall y now g mv,
  mval_has_type (composites publisher) (Tstruct (nm_out_struct publisher)) y ->
  published_value publisher y now g out mv -> cycle_sent_okb y (sent publisher out mv) = true.
Proof.
  intros y now g mv Ty P.
  exact (seq_sent publisher out (mkoutrel "L" "out" dlen) (mkoutrel "E0" "out" (delem 0)) y now g mv
           (or_introl eq_refl) eq_refl eq_refl (or_intror (or_introl eq_refl)) eq_refl eq_refl
           ltac:(vm_compute; reflexivity) ltac:(vm_compute; reflexivity)
           ltac:(repeat split; vm_compute; reflexivity) Ty P).
Qed.

Lemma run_ok_pub_seq: forall n t, run_ok publisher pctx n t -> pub_okb cycle_sent_okb t = true.
Proof.
  intros n t R. apply (run_ok_pub nat publisher pctx out cycle_sent_okb n t eq_refl pctx_controller_wt); auto.
  intros y now g mv Ty P. apply (cycle_sent y now g mv Ty P).
Qed.

(** *** Mutants of the published sequence *)

Definition pcheck (p : program) (n : nat) : bool :=
  match run_trace 4000 p pctx n with
  | Some t => pub_okb cycle_sent_okb t
  | None => true
  end.

Lemma prefute: forall p n, pcheck p n = false -> ~ node_ddc publisher p.
Proof.
  intros p n H D. unfold pcheck in H.
  destruct (run_trace 4000 p pctx n) as [t|] eqn:R; [|discriminate].
  destruct (D nat pctx n pctx_arrivals_wt pctx_controller_wt) as [_ All].
  rewrite (run_ok_pub_seq n t (All t (run_trace_sound _ pctx 4000 p n t R))) in H. discriminate.
Qed.

(** The generated program passes (as T2 says it must). *)
Example publisher_passes: pcheck publisher_prog 6 = true.
Proof. vm_compute. reflexivity. Qed.

(** The copies of the output glue (after the zeroing) changed by [g]. *)
Definition on_out_copies (g : list statement -> list statement) (p : program) : program :=
  on_def (output_glue_name "out")
    (on_body (fun s => match s with
                       | Ssequence (Ssequence zero copies) strs => Ssequence (Ssequence zero (on_seq g copies)) strs
                       | _ => s
                       end)) p.

(** (q3) the length output written into the wrong field of the sequence:
    [truncated] instead of [len] (the length stays 0) *)
Definition m_len_wrong_field : program :=
  on_out_copies (map (on_copy_dst (rename_field "len" "truncated"))) publisher_prog.
Theorem m_len_wrong_field_refuted: ~ node_ddc publisher m_len_wrong_field.
Proof. apply (prefute _ 2). vm_compute. reflexivity. Qed.

(** (q4) element 0's output written into element 1 (an off-by-one index) *)
Definition shift_dst (e : expr) : expr :=
  match e with
  | Eindex a (Econst_int 0 ti) t => Eindex a (Econst_int 1 ti) t
  | _ => e
  end.
Definition m_elem_off : program := on_out_copies (map (on_copy_dst shift_dst)) publisher_prog.
Theorem m_elem_off_refuted: ~ node_ddc publisher m_elem_off.
Proof. apply (prefute _ 2). vm_compute. reflexivity. Qed.

(** (q5) the length never written: the copy of [L] left out *)
Definition m_len_missing : program := on_out_copies (remove_nth 0) publisher_prog.
Theorem m_len_missing_refuted: ~ node_ddc publisher m_len_missing.
Proof. apply (prefute _ 2). vm_compute. reflexivity. Qed.

(** ** Policy reject *)

(** The scanner whose [ranges] has policy reject: its struct is
    [ros_rseq_float32_4] ([Environment.reject_name]).  The same six scans
    arrive, then two spins of two scans each on a queue of 1: in spin 6 an
    accepted scan of length 2 followed by a rejected one of length 6,
    which pushes it out of the queue (nothing is delivered); in spin 7 a
    rejected one followed by an accepted one of length 2. *)
Definition rseq4 : msgdef :=
  mkmsgdef "ros_rseq_float32_4" [("len", FTprim Puint32); ("truncated", FTprim Pbool);
                                 ("data", FTarray (FTprim Pfloat32) 4)].
Definition laser_scan_r : msgdef :=
  mkmsgdef "sensor_msgs_LaserScan" [("angle_min", FTprim Pfloat32); ("ranges", FTmsg "ros_rseq_float32_4")].

Definition rejector : node_model := {|
  nm_name := "rejector"; nm_period_ms := 20; nm_ctrl := "Controller";
  nm_in_var := "Controller_U"; nm_in_struct := "ExtU_Controller_T";
  nm_inputs := [("R1", FTprim Pfloat32); ("Len", FTprim Puint32); ("Trunc", FTprim Pbool)];
  nm_out_var := "Controller_Y"; nm_out_struct := "ExtY_Controller_T";
  nm_outputs := [("Out1", FTprim Pfloat64)];
  nm_msgs := [rseq4; laser_scan_r; geometry_msgs_Vector3; geometry_msgs_Twist];
  nm_topics := [scan; cmd];
  nm_inrels := nm_inrels scanner;
  nm_outrels := nm_outrels scanner;
  nm_timeouts := []; nm_fallbacks := []; nm_drels := []; nm_stamps := []; nm_stamp_from := [];
  nm_strings := [] |}.

Definition rejector_result : res program := Eval vm_compute in generate rejector.
Definition rejector_prog : program :=
  Eval vm_compute in match rejector_result with OK p => p | Error _ => mkprogram [] [] "" end.

Lemma rejector_generates: generate rejector = OK rejector_prog.
Proof. vm_compute. reflexivity. Qed.

Definition rctx : ros_context unit :=
  mkctx (fun k => match k with
                  | 6%nat => [mkarrival "/scan" (scan_msg 2 [r5; r6; junk; junk]) 0;
                              mkarrival "/scan" (scan_msg 6 [r5; r7; r7; r7]) 0]
                  | 7%nat => [mkarrival "/scan" (scan_msg 6 [r5; r7; r7; r7]) 0;
                              mkarrival "/scan" (scan_msg 2 [r5; r8; junk; junk]) 0]
                  | _ => match nth_error scans k with
                         | Some (l, xs) => [mkarrival "/scan" (scan_msg l xs) 0]
                         | None => []
                         end
                  end)
        (fun _ => 0%Z) tt (fun _ _ => (tt, y_out)) Ros1.

Lemma rctx_arrivals_wt: arrivals_wt rejector rctx.
Proof.
  intros k a tp H Htp _. apply mval_typecheck_iff.
  simpl in Htp. destruct Htp as [<-|[]].
  do 8 (destruct k as [|k]; [simpl in H; repeat (destruct H as [<-|H]; [vm_compute; reflexivity|]); contradiction|]).
  simpl in H. destruct k; contradiction.
Qed.

Lemma rctx_controller_wt: controller_wt rejector rctx.
Proof. intros s u. apply mval_typecheck_iff. vm_compute. reflexivity. Qed.

(** The controller never sees a scan longer than 4: after the scan of
    length 4 (cycle 3), the scans of lengths 5 and 8 are dropped and it
    keeps [ranges[1] = 6.0] and the length 4; in cycle 6 the rejected scan
    pushed the accepted one out of the queue, so it still keeps them; in
    cycle 7 it gets the accepted scan of length 2 ([ranges[1] = 8.0]).
    [truncated] is never set. *)
Example rejector_run:
  match run_trace 4000 rejector_prog rctx 8 with
  | Some t => inputs_of t =
      [(Some 0, Some 0, Some 0); (Some 0, Some 1, Some 0); (Some 0x40C00000, Some 3, Some 0);
       (Some 0x40C00000, Some 4, Some 0); (Some 0x40C00000, Some 4, Some 0); (Some 0x40C00000, Some 4, Some 0);
       (Some 0x40C00000, Some 4, Some 0); (Some 0x41000000, Some 2, Some 0)]%Z
  | None => False
  end.
Proof. vm_compute. reflexivity. Qed.

Definition rcheck : program -> nat -> bool := check_in rejector rctx 4000.

Lemma rrefute: forall p n, rcheck p n = false -> ~ node_ddc rejector p.
Proof. exact (refute_in rejector rctx 4000 rctx_arrivals_wt rctx_controller_wt). Qed.

(** The generated program passes (as T2 says it must). *)
Example rejector_passes: rcheck rejector_prog 8 = true.
Proof. vm_compute. reflexivity. Qed.

(** (q6) the scanner's program, whose [ranges] has policy truncate,
    against the rejector's model: it hands the controller the truncated
    scans of lengths 5 and 8 (length 4, [truncated] 1), which T2 for
    policy reject forbids: an over-long message is never delivered. *)
Theorem truncating_program_refuted: ~ node_ddc rejector scanner_prog.
Proof. apply (rrefute _ 5). vm_compute. reflexivity. Qed.

(** ** Sequences of messages *)

Local Open Scope Z_scope.

(** [Environment.clamp] on a sequence of at most 2 poses, each with a
    string of at most 4 bytes: the sequence and each kept pose's string
    are capped, and a missing pose is the zero pose. *)
Definition nested_ce : composite_env :=
  [Composite "ros_string4" [("len", tuint); ("truncated", tuchar); ("data", Tarray tuchar 4)];
   Composite "Pose" [("frame", Tstruct "ros_string4"); ("x", tdouble)];
   Composite "ros_seq_Pose_2" [("len", tuint); ("truncated", tuchar); ("data", Tarray (Tstruct "Pose") 2)]].

Example nested_ce_wf : wf_composites nested_ce.
Proof. vm_compute. reflexivity. Qed.

Definition bytes (l : list Z) : mval := MVarray (map (fun b => MVscalar (Vint b)) l).
Definition str (len : Z) (l : list Z) : mval :=
  MVstruct [("len", MVscalar (Vint len)); ("truncated", MVscalar (Vint 0)); ("data", bytes l)].
Definition pose (s : mval) (x : Z) : mval := MVstruct [("frame", s); ("x", MVscalar (f64 x))].
Definition poses (len : Z) (ps : list mval) : mval :=
  MVstruct [("len", MVscalar (Vint len)); ("truncated", MVscalar (Vint 0)); ("data", MVarray ps)].

(** Three poses announced, two carried: a frame of 6 bytes (4 kept, truncated)
    and one of 2 (its junk past the length zeroed). *)
Example nested_truncated :
  clamp nested_ce (Tstruct "ros_seq_Pose_2")
    (poses 3 [pose (str 6 [97; 98; 99; 100]) 0x3FF0000000000000; pose (str 2 [101; 102; 7; 7]) 0])
  = MVstruct [("len", MVscalar (Vint 2)); ("truncated", MVscalar (Vint 1));
              ("data", MVarray [pose (MVstruct [("len", MVscalar (Vint 4)); ("truncated", MVscalar (Vint 1));
                                                ("data", bytes [97; 98; 99; 100])]) 0x3FF0000000000000;
                                pose (MVstruct [("len", MVscalar (Vint 2)); ("truncated", MVscalar (Vint 0));
                                                ("data", bytes [101; 102; 0; 0])]) 0])].
Proof. vm_compute. reflexivity. Qed.

(** One pose announced: the second element is the zero pose. *)
Example nested_short :
  clamp nested_ce (Tstruct "ros_seq_Pose_2")
    (poses 1 [pose (str 1 [97; 7; 7; 7]) 0x3FF0000000000000; pose (str 2 [101; 102; 7; 7]) 0])
  = MVstruct [("len", MVscalar (Vint 1)); ("truncated", MVscalar (Vint 0));
              ("data", MVarray [pose (str 1 [97; 0; 0; 0]) 0x3FF0000000000000;
                                zero_mval nested_ce (Tstruct "Pose")])].
Proof. vm_compute. reflexivity. Qed.
