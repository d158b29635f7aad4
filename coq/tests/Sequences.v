(** * Bounded sequences (issue 15): the environment's conversion, a run, and mutants *)

(** A scanner node: it subscribes to [/scan], whose [sensor_msgs/LaserScan]
    message carries [ranges] as a bounded sequence of at most 4 [float32]
    ([ros_seq_float32_4]), and feeds the controller [ranges[1]], the
    received length and whether the scan was truncated, through ordinary
    input relations on the leaves [ranges.data[1]], [ranges.len] and
    [ranges.truncated].  Six scans arrive, of lengths 0, 1, 3, 4, 5 and 8
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
  nm_inputs := [("R1", Pfloat32); ("Len", Puint32); ("Trunc", Pbool)];
  nm_out_var := "Controller_Y"; nm_out_struct := "ExtY_Controller_T";
  nm_outputs := [("Out1", Pfloat64)];
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
        (fun _ => 0%Z) tt (fun _ _ => (tt, y_out)).

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

Definition scheck (p : program) (n : nat) : bool :=
  match run_trace 4000 p sctx n with
  | Some t => run_okb scanner sctx n t
  | None => true
  end.

Lemma srefute: forall p n, scheck p n = false -> ~ node_ddc scanner p.
Proof.
  intros p n H D. unfold scheck in H.
  destruct (run_trace 4000 p sctx n) as [t|] eqn:R; [|discriminate].
  destruct (D unit sctx n sctx_arrivals_wt sctx_controller_wt) as [_ All].
  rewrite (run_ok_okb _ _ _ _ _ (All t (run_trace_sound _ sctx 4000 p n t R))) in H. discriminate.
Qed.

(** The generated program passes (as T2 says it must). *)
Example scanner_passes: scheck scanner_prog 6 = true.
Proof. vm_compute. reflexivity. Qed.

(** The body of [input_glue] changed by [g]. *)
Definition on_input_glue (g : statement -> statement) (p : program) : program :=
  mkprogram (prog_types p)
    (map (fun d : ident * globdef => if string_dec (fst d) "input_glue"
                   then match snd d with
                        | Gfun (Internal f) =>
                            (fst d, Gfun (Internal (mkfunction (fn_return f) (fn_params f) (fn_vars f)
                                                                (fn_temps f) (g (fn_body f)))))
                        | _ => d
                        end
                   else d) (prog_defs p))
    (prog_main p).

Fixpoint map_exprs (h : expr -> expr) (s : statement) : statement :=
  match s with
  | Ssequence a b => Ssequence (map_exprs h a) (map_exprs h b)
  | Sset x e => Sset x (h e)
  | Sassign l e => Sassign l (h e)
  | _ => s
  end.

(** (q1) the element read one index off: [ranges.data[2]] for [ranges.data[1]] *)
Definition shift_index (e : expr) : expr :=
  match e with
  | Eindex a (Econst_int 1 ti) t => Eindex a (Econst_int 2 ti) t
  | _ => e
  end.
Definition m_index_off : program := on_input_glue (map_exprs shift_index) scanner_prog.
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
    reaches the bounded sequence through no other one. *)
Example ranges_unbounded_path:
  unbounded_path sce (Tstruct "sensor_msgs_LaserScan") (path_steps [PField "ranges"]) = true
  /\ type_at sce (Tstruct "sensor_msgs_LaserScan") (path_steps [PField "ranges"]) = Some (Tstruct "ros_seq_float32_4")
  /\ bounded_name "ros_seq_float32_4" = true
  /\ struct_members sce "ros_seq_float32_4"
     = Some [("len", Tint I32 Unsigned); ("truncated", Tint I8 Unsigned); ("data", Tarray (Tfloat F32) 4)].
Proof. vm_compute. repeat split. Qed.
