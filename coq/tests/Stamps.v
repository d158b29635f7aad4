(** * Stamps (rule 4.13): the generator, the interpreter, and mutants *)

(** The LandShark node with its published [TwistStamped] stamped with
    the cycle's ROS time: [generate] accepts it and refuses bad stamps
    naming the culprit; the interpreter runs it in an environment whose
    cycles have known times, and the published stamp is the cycle's
    [sec] and [nsec]; two mutants of the stamp code (the two fields
    swapped, the stamp left out) are refuted against T2. *)

From Coq Require Import String List ZArith Lia.
From Flocq Require Import IEEE754.Binary IEEE754.Bits.
From ROSGen Require Import FloatBits Errors Syntax Values Memory Environment Semantics Interp Interpproof
  NodeModel Wellformed Generator Generatorspec DDC Loopproof.
From ROSGenTests Require Import LandShark.
From ROSGenTests Require Mutants.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope list_scope.

Definition with_stamps (m : node_model) (l : list (ident * path)) : node_model :=
  reshape m (nm_inputs m) (nm_msgs m) (nm_timeouts m) (nm_fallbacks m) (nm_drels m) l (nm_stamp_from m) (nm_strings m).

Definition header_stamp : path := [PField "header"; PField "stamp"].

Definition stamped : node_model :=
  with_stamps landshark [("landshark_control_base_velocity", header_stamp)].

(** ** The generator *)

Example stamped_wf: wf stamped = true.
Proof. vm_compute. reflexivity. Qed.

Definition stamped_result : res program := Eval vm_compute in generate stamped.
Definition stamped_prog : program :=
  Eval vm_compute in match stamped_result with OK p => p | Error _ => mkprogram [] [] "" end.

Lemma stamped_generates: generate stamped = OK stamped_prog.
Proof. vm_compute. reflexivity. Qed.

(** The time functions are declared, and only by a stamping node. *)
Example time_externals_declared:
  find_def stamped_prog "ros_time_sec" = Some (Gfun (External EF_ros_time_sec [] (Tint I32 Unsigned)))
  /\ find_def landshark_prog "ros_time_sec" = None.
Proof. vm_compute. split; reflexivity. Qed.

Example refuse_stamp_subscribed:
  refused (with_stamps landshark [("landshark_gps_velocity", header_stamp)])
    "Generator: bad stamp (rule 4.13) on topic 'landshark_gps_velocity': '.header.stamp' must be a time field of a published message that no output relation writes".
Proof. vm_compute. reflexivity. Qed.

Example refuse_stamp_not_time:
  refused (with_stamps landshark [("landshark_control_base_velocity", [PField "header"])])
    "Generator: bad stamp (rule 4.13) on topic 'landshark_control_base_velocity': '.header' must be a time field of a published message that no output relation writes".
Proof. vm_compute. reflexivity. Qed.

Example refuse_stamp_twice:
  refused (with_stamps landshark [("landshark_control_base_velocity", header_stamp);
                                  ("landshark_control_base_velocity", header_stamp)])
    "Generator: topic stamped twice: 'landshark_control_base_velocity'".
Proof. vm_compute. reflexivity. Qed.

(** An output relation writing into the stamp conflicts with it. *)
Definition stamp_and_relation : node_model :=
  {| nm_name := nm_name stamped; nm_period_ms := nm_period_ms stamped; nm_ctrl := nm_ctrl stamped;
     nm_in_var := nm_in_var stamped; nm_in_struct := nm_in_struct stamped;
     nm_inputs := nm_inputs stamped; nm_out_var := nm_out_var stamped;
     nm_out_struct := nm_out_struct stamped; nm_outputs := [("Out1", FTprim Pfloat64); ("Sec", FTprim Puint32)];
     nm_msgs := nm_msgs stamped; nm_topics := nm_topics stamped; nm_inrels := nm_inrels stamped;
     nm_outrels := nm_outrels stamped ++
                   [mkoutrel "Sec" "landshark_control_base_velocity" (header_stamp ++ [PField "sec"])%list];
     nm_timeouts := []; nm_fallbacks := []; nm_drels := []; nm_stamps := nm_stamps stamped; nm_stamp_from := nm_stamp_from stamped; nm_strings := [] |}.

Example refuse_stamp_overwritten:
  refused stamp_and_relation
    "Generator: bad stamp (rule 4.13) on topic 'landshark_control_base_velocity': '.header.stamp' must be a time field of a published message that no output relation writes".
Proof. vm_compute. reflexivity. Qed.

(** ** A run with known times *)

Definition f_one : float64 := float64_of_bits 0x3FF0000000000000.

Definition ce : composite_env := composites stamped.
Definition TS : type := Tstruct "geometry_msgs_TwistStamped".

Definition msg_x (x : float64) : mval :=
  match mval_set (zero_mval ce TS) (path_steps twist_x) (MVscalar (Vfloat x)) with
  | Some v => v
  | None => MVscalar Vundef
  end.

Definition y_one : mval := MVstruct [("Out1", MVscalar (Vfloat f_one))].

(** Cycle [k] is read at [k] s + 250 ms (and 1,000 s + 1 ns for the
    fourth, so that [sec] has more than one digit and [nsec] is odd). *)
Definition clock (k : nat) : Z :=
  match k with
  | 3%nat => 1000000000001
  | _ => Z.of_nat k * 1000000000 + 250000000
  end.

Definition ctx : ros_context unit :=
  mkctx (fun k => match k with
                  | O => [mkarrival (tp_name left_wheel) (msg_x f_one) 7]
                  | _ => []
                  end)
        clock tt (fun _ _ => (tt, y_one)) Ros1.

Lemma ctx_arrivals_wt: arrivals_wt stamped ctx.
Proof.
  intros k a tp H Htp _. apply mval_typecheck_iff.
  destruct k as [|k]; simpl in H; [|contradiction].
  destruct H as [<-|[]]. simpl in Htp.
  destruct Htp as [<-|[<-|[<-|[]]]]; vm_compute; reflexivity.
Qed.

Lemma ctx_controller_wt: controller_wt stamped ctx.
Proof. intros s u. apply mval_typecheck_iff. vm_compute. reflexivity. Qed.

(** The stamps ([sec], [nsec]) of the published messages of a trace. *)
Definition int_at (mv : mval) (p : path) : option Z :=
  match mval_get mv (path_steps p) with Some (MVscalar (Vint n)) => Some n | _ => None end.

Definition stamps_of (t : trace) : list (option Z * option Z) :=
  flat_map (fun e => match e with
                     | Epublish _ mv => [(int_at mv (header_stamp ++ [PField "sec"])%list,
                                          int_at mv (header_stamp ++ [PField "nsec"])%list)]
                     | _ => []
                     end) t.

(** Three cycles: stamps (1 s, 250 ms), (2 s, 250 ms), (1,000 s, 1 ns). *)
Example stamped_run:
  match run_trace 2000 stamped_prog ctx 3 with
  | Some t => stamps_of t = [(Some 1%Z, Some 250000000%Z); (Some 2%Z, Some 250000000%Z); (Some 1000%Z, Some 1%Z)]
  | None => False
  end.
Proof. vm_compute. reflexivity. Qed.

(** ** Mutants *)

(** What T2 says of the stamps of a run of [n] cycles of this node: the
    [i]-th publication carries the time of cycle [i]. *)
Definition stamps_expected (n : nat) : list (option Z * option Z) :=
  map (fun i => (Some (time_sec (clock (S i))), Some (time_nsec (clock (S i))))) (seq 0 n).

Lemma stamps_of_app: forall t1 t2 : trace, stamps_of (t1 ++ t2)%list = (stamps_of t1 ++ stamps_of t2)%list.
Proof. intros; unfold stamps_of; apply flat_map_app. Qed.

(** A stamp, outside any bounded sequence, is sent as the glue wrote it
    ([sent_scalar]). *)
Lemma int_at_sent:
  forall m tp mv p t x,
  mval_has_type (composites m) (Tstruct (tp_msg tp)) mv ->
  unbounded_path (composites m) (Tstruct (tp_msg tp)) (path_steps p) = true ->
  type_at (composites m) (Tstruct (tp_msg tp)) (path_steps p) = Some t ->
  mval_get mv (path_steps p) = Some (MVscalar x) ->
  int_at (sent m tp mv) p = int_at mv p.
Proof.
  intros m tp mv p t x T U Ty G. unfold int_at.
  rewrite (sent_scalar m tp mv p t x T U Ty G), G. reflexivity.
Qed.

(** The stamps of one cycle of a node with one published topic: those of
    the command the glue wrote. *)
Lemma int_at_sent_stamp:
  forall m (u y : mval) tp mv,
  published m = [tp] ->
  mval_has_type (composites m) (Tstruct (tp_msg tp)) mv ->
  unbounded_path (composites m) (Tstruct (tp_msg tp)) (path_steps (header_stamp ++ [PField "sec"])) = true ->
  unbounded_path (composites m) (Tstruct (tp_msg tp)) (path_steps (header_stamp ++ [PField "nsec"])) = true ->
  type_at (composites m) (Tstruct (tp_msg tp)) (path_steps (header_stamp ++ [PField "sec"])) = Some (Tint I32 Unsigned) ->
  type_at (composites m) (Tstruct (tp_msg tp)) (path_steps (header_stamp ++ [PField "nsec"])) = Some (Tint I32 Unsigned) ->
  stamps_of (Estep u y :: publish_events m (published m) [mv] ++ [Esleep (nm_period_ms m)])
  = [(int_at mv (header_stamp ++ [PField "sec"]), int_at mv (header_stamp ++ [PField "nsec"]))].
Proof.
  intros m u y tp mv Pm T U1 U2 Ty1 Ty2.
  destruct (mval_get_has_type _ _ _ _ _ T Ty1) as (x1 & Gs & Tx1). inversion Tx1; subst; try discriminate.
  destruct (mval_get_has_type _ _ _ _ _ T Ty2) as (x2 & Gn & Tx2). inversion Tx2; subst; try discriminate.
  rewrite Pm. unfold stamps_of, publish_events. cbn [map combine fst snd flat_map app].
  exact (f_equal (fun a => [a]) (f_equal2 pair (int_at_sent m tp mv _ _ _ T U1 Ty1 Gs) (int_at_sent m tp mv _ _ _ T U2 Ty2 Gn))).
Qed.

Lemma run_ok_stamps:
  forall n t, run_ok stamped ctx n t -> stamps_of t = stamps_expected n.
Proof.
  intros n t (s & evs & _ & -> & C).
  rewrite stamps_of_app. replace (stamps_of (start_events stamped)) with (@nil (option Z * option Z))
    by (vm_compute; reflexivity).
  simpl app. unfold stamps_expected.
  assert (G: forall k, (k <= n)%nat ->
             stamps_of (concat (map evs (seq (n - k) k)))
             = map (fun i => (Some (time_sec (clock (S i))), Some (time_nsec (clock (S i)))))
                   (seq (n - k) k)).
  { induction k as [|k IH]; intros Hk; simpl; auto.
    rewrite stamps_of_app.
    destruct (C (n - S k)%nat ltac:(lia)) as (u & y & mvs & E & _ & _ & PV).
    rewrite E. simpl published in PV.
    inversion PV as [|tp mv tps mvs' P F]; subst. inversion F; subst.
    destruct P as (T & _ & ST & _).
    destruct (ST header_stamp eq_refl) as [Gs Gn].
    assert (R1: time_is_ros2 (nm_msgs stamped) = false) by (vm_compute; reflexivity).
    unfold stamp_sec, stamp_nsec, time_nsec_field in Gs, Gn. rewrite R1 in Gs, Gn.
    rewrite (int_at_sent_stamp stamped u y base mv eq_refl T ltac:(vm_compute; reflexivity) ltac:(vm_compute; reflexivity)
               ltac:(vm_compute; reflexivity) ltac:(vm_compute; reflexivity)).
    simpl in Gs, Gn. simpl. unfold int_at. simpl. rewrite Gs, Gn. f_equal.
    replace (S (n - S k)) with (n - k)%nat by lia. apply IH. lia. }
  specialize (G n (le_n n)). rewrite Nat.sub_diag in G. exact G.
Qed.

Definition stamp_eq_dec : forall a b : option Z * option Z, {a = b} + {a <> b}.
Proof. decide equality; decide equality; apply Z.eq_dec. Defined.

Definition check (p : program) (n : nat) : bool :=
  match run_trace 2000 p ctx n with
  | Some t => if list_eq_dec stamp_eq_dec (stamps_of t) (stamps_expected n) then true else false
  | None => true
  end.

Lemma refute: forall p n, check p n = false -> ~ node_ddc stamped p.
Proof.
  intros p n H D. unfold check in H.
  destruct (run_trace 2000 p ctx n) as [t|] eqn:R; [|discriminate].
  destruct (D unit ctx n ctx_arrivals_wt ctx_controller_wt) as [_ All].
  rewrite (run_ok_stamps n t (All t (run_trace_sound _ ctx 2000 p n t R))) in H.
  destruct (list_eq_dec stamp_eq_dec (stamps_expected n) (stamps_expected n)); congruence.
Qed.

(** The generated program passes (as T2 says it must). *)
Example stamped_passes: check stamped_prog 3 = true.
Proof. vm_compute. reflexivity. Qed.

(** The output glue's body changed by [g]. *)
Definition on_output_glue (g : statement -> statement) (p : program) : program :=
  mkprogram (prog_types p)
    (map (fun d : ident * globdef => if string_dec (fst d) "output_glue_landshark_control_base_velocity"
                   then match snd d with
                        | Gfun (Internal f) =>
                            (fst d, Gfun (Internal (mkfunction (fn_return f) (fn_params f) (fn_vars f)
                                                                (fn_temps f) (g (fn_body f)))))
                        | _ => d
                        end
                   else d) (prog_defs p))
    (prog_main p).

(** [ros_time_sec] and [ros_time_nsec] exchanged in the stamp code. *)
Fixpoint swap_time (s : statement) : statement :=
  match s with
  | Ssequence a b => Ssequence (swap_time a) (swap_time b)
  | Scall o (Evar f ty) args =>
      Scall o (Evar (if string_dec f "ros_time_sec" then "ros_time_nsec"
                     else if string_dec f "ros_time_nsec" then "ros_time_sec" else f) ty) args
  | _ => s
  end.

(** (s1) the seconds and nanoseconds swapped *)
Definition m_stamp_swapped : program :=
  on_output_glue (fun b => match b with Ssequence (Ssequence base st) strs => Ssequence (Ssequence base (swap_time st)) strs | _ => b end)
                 stamped_prog.
Theorem m_stamp_swapped_refuted: ~ node_ddc stamped m_stamp_swapped.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (s2) the stamp left out: the header keeps the zero time *)
Definition m_stamp_missing : program :=
  on_output_glue (fun b => match b with Ssequence (Ssequence base _) strs => Ssequence base strs | _ => b end) stamped_prog.
Theorem m_stamp_missing_refuted: ~ node_ddc stamped m_stamp_missing.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (s3) the stamp written before the zeroing, which then erases it *)
Definition m_stamp_first : program :=
  on_output_glue (fun b => match b with Ssequence (Ssequence base st) strs => Ssequence (Ssequence st base) strs | _ => b end) stamped_prog.
Theorem m_stamp_first_refuted: ~ node_ddc stamped m_stamp_first.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** ** Stamps copied from a subscribed topic *)

(** [copied]: LandShark whose command carries the [header.stamp] of the
    newest GPS message (zero before the first). *)
Definition copied : node_model :=
  {| nm_name := nm_name stamped; nm_period_ms := nm_period_ms stamped; nm_ctrl := nm_ctrl stamped;
     nm_in_var := nm_in_var stamped; nm_in_struct := nm_in_struct stamped;
     nm_inputs := nm_inputs stamped; nm_out_var := nm_out_var stamped;
     nm_out_struct := nm_out_struct stamped; nm_outputs := nm_outputs stamped;
     nm_msgs := nm_msgs stamped; nm_topics := nm_topics stamped; nm_inrels := nm_inrels stamped;
     nm_outrels := nm_outrels stamped; nm_timeouts := []; nm_fallbacks := []; nm_drels := [];
     nm_stamps := nm_stamps stamped;
     nm_stamp_from := [("landshark_control_base_velocity", ("landshark_gps_velocity", header_stamp))]; nm_strings := [] |}.

Definition copied_result : res program := Eval vm_compute in generate copied.
Definition copied_prog : program :=
  Eval vm_compute in match copied_result with OK p => p | Error _ => mkprogram [] [] "" end.

Lemma copied_generates: generate copied = OK copied_prog.
Proof. vm_compute. reflexivity. Qed.

Definition with_stamp_from (l : list (ident * (ident * path))) : node_model :=
  {| nm_name := nm_name copied; nm_period_ms := nm_period_ms copied; nm_ctrl := nm_ctrl copied;
     nm_in_var := nm_in_var copied; nm_in_struct := nm_in_struct copied;
     nm_inputs := nm_inputs copied; nm_out_var := nm_out_var copied;
     nm_out_struct := nm_out_struct copied; nm_outputs := nm_outputs copied;
     nm_msgs := nm_msgs copied; nm_topics := nm_topics copied; nm_inrels := nm_inrels copied;
     nm_outrels := nm_outrels copied; nm_timeouts := []; nm_fallbacks := []; nm_drels := [];
     nm_stamps := nm_stamps copied; nm_stamp_from := l; nm_strings := [] |}.

(** A source that is published, or not a [time] field. *)
Example refuse_source_published:
  refused (with_stamp_from [("landshark_control_base_velocity", ("landshark_control_base_velocity", header_stamp))])
    "Generator: bad stamp source (rule 4.13) for topic 'landshark_control_base_velocity': 'landshark_control_base_velocity.header.stamp' must be a time field of a subscribed topic's message, for a stamped topic".
Proof. vm_compute. reflexivity. Qed.

Example refuse_source_not_time:
  refused (with_stamp_from [("landshark_control_base_velocity", ("landshark_gps_velocity", [PField "header"]))])
    "Generator: bad stamp source (rule 4.13) for topic 'landshark_control_base_velocity': 'landshark_gps_velocity.header' must be a time field of a subscribed topic's message, for a stamped topic".
Proof. vm_compute. reflexivity. Qed.

(** A message whose [header.stamp] is [(sec, nsec)]. *)
Definition msg_stamp (sec nsec : Z) : mval :=
  match mval_set (zero_mval ce TS) (path_steps (header_stamp ++ [PField "sec"])) (MVscalar (Vint sec)) with
  | Some v => match mval_set v (path_steps (header_stamp ++ [PField "nsec"])) (MVscalar (Vint nsec)) with
              | Some v' => v'
              | None => MVscalar Vundef
              end
  | None => MVscalar Vundef
  end.

(** The left wheel's stamp (1 s, 1 ns) and the GPS's (5 s, 7 ns) for the
    first cycle, the GPS's (6 s, 8 ns) for the second, nothing for the
    third. *)
Definition cctx : ros_context unit :=
  mkctx (fun k => match k with
                  | O => [mkarrival (tp_name left_wheel) (msg_stamp 1 1) 3;
                          mkarrival (tp_name gps) (msg_stamp 5 7) 4]
                  | 1%nat => [mkarrival (tp_name gps) (msg_stamp 6 8) 5]
                  | _ => []
                  end)
        clock tt (fun _ _ => (tt, y_one)) Ros1.

Lemma cctx_arrivals_wt: arrivals_wt copied cctx.
Proof.
  intros k a tp H Htp _. apply mval_typecheck_iff.
  simpl in Htp. destruct Htp as [<-|[<-|[<-|[]]]];
    destruct k as [|[|k]]; simpl in H; repeat destruct H as [H|H]; try contradiction;
    subst a; vm_compute; reflexivity.
Qed.

Lemma cctx_controller_wt: controller_wt copied cctx.
Proof. intros s u. apply mval_typecheck_iff. vm_compute. reflexivity. Qed.

Example copied_run:
  match run_trace 2000 copied_prog cctx 3 with
  | Some t => stamps_of t = [(Some 5%Z, Some 7%Z); (Some 6%Z, Some 8%Z); (Some 6%Z, Some 8%Z)]
  | None => False
  end.
Proof. vm_compute. reflexivity. Qed.

(** What T2 says: the [i]-th publication carries the stamp of the newest
    GPS message up to spin [i]. *)
Definition copied_expected (n : nat) : list (option Z * option Z) :=
  map (fun i => (int_at (newest_by copied cctx i "landshark_gps_velocity") (header_stamp ++ [PField "sec"]),
                 int_at (newest_by copied cctx i "landshark_gps_velocity") (header_stamp ++ [PField "nsec"])))
      (seq 0 n).

Lemma run_ok_copied:
  forall n t, run_ok copied cctx n t -> stamps_of t = copied_expected n.
Proof.
  intros n t (s & evs & _ & -> & C).
  rewrite stamps_of_app. replace (stamps_of (start_events copied)) with (@nil (option Z * option Z))
    by (vm_compute; reflexivity).
  simpl app. unfold copied_expected.
  assert (G: forall k, (k <= n)%nat ->
             stamps_of (concat (map evs (seq (n - k) k)))
             = map (fun i => (int_at (newest_by copied cctx i "landshark_gps_velocity") (header_stamp ++ [PField "sec"]),
                              int_at (newest_by copied cctx i "landshark_gps_velocity") (header_stamp ++ [PField "nsec"])))
                   (seq (n - k) k)).
  { induction k as [|k IH]; intros Hk; simpl; auto.
    rewrite stamps_of_app.
    destruct (C (n - S k)%nat ltac:(lia)) as (u & y & mvs & E & _ & _ & PV).
    rewrite E. simpl published in PV.
    inversion PV as [|tp mv tps mvs' P F]; subst. inversion F; subst.
    destruct P as (T & _ & ST & _).
    destruct (ST header_stamp eq_refl) as [Gs Gn].
    assert (R1: time_is_ros2 (nm_msgs copied) = false) by (vm_compute; reflexivity).
    unfold stamp_nsec, time_nsec_field in Gn. rewrite R1 in Gn.
    rewrite (int_at_sent_stamp copied u y base mv eq_refl T ltac:(vm_compute; reflexivity) ltac:(vm_compute; reflexivity)
               ltac:(vm_compute; reflexivity) ltac:(vm_compute; reflexivity)).
    simpl. unfold int_at. simpl in Gs, Gn |- *. rewrite Gs, Gn. f_equal.
    replace (S (n - S k)) with (n - k)%nat by lia. apply IH. lia. }
  specialize (G n (le_n n)). rewrite Nat.sub_diag in G. exact G.
Qed.

Definition ccheck (p : program) (n : nat) : bool :=
  match run_trace 2000 p cctx n with
  | Some t => if list_eq_dec stamp_eq_dec (stamps_of t) (copied_expected n) then true else false
  | None => true
  end.

Lemma crefute: forall p n, ccheck p n = false -> ~ node_ddc copied p.
Proof.
  intros p n H D. unfold ccheck in H.
  destruct (run_trace 2000 p cctx n) as [t|] eqn:R; [|discriminate].
  destruct (D unit cctx n cctx_arrivals_wt cctx_controller_wt) as [_ All].
  rewrite (run_ok_copied n t (All t (run_trace_sound _ cctx 2000 p n t R))) in H.
  destruct (list_eq_dec stamp_eq_dec (copied_expected n) (copied_expected n)); congruence.
Qed.

Example copied_passes: ccheck copied_prog 3 = true.
Proof. vm_compute. reflexivity. Qed.

(** (s4) the stamp copied from the wrong topic: the left wheel's. *)
Fixpoint rename_msg (x x' : ident) (e : expr) : expr :=
  match e with
  | Evar y ty => Evar (if string_dec y x then x' else y) ty
  | Efield a f ty => Efield (rename_msg x x' a) f ty
  | _ => e
  end.

Fixpoint from_left (s : statement) : statement :=
  match s with
  | Ssequence a b => Ssequence (from_left a) (from_left b)
  | Sset t e => Sset t (rename_msg "landshark_gps_velocity_msg" "landshark_left_wheel_velocity_msg" e)
  | _ => s
  end.

Definition m_stamp_wrong_topic : program :=
  on_output_glue (fun b => match b with Ssequence (Ssequence base st) strs => Ssequence (Ssequence base (from_left st)) strs | _ => b end) copied_prog.
Theorem m_stamp_wrong_topic_refuted: ~ node_ddc copied m_stamp_wrong_topic.
Proof. apply (crefute _ 1). vm_compute. reflexivity. Qed.

(** (s5) The GPS callback does not copy the stamp that the command
    carries: a generator whose [read_paths] forgot copied stamps.  Its
    body copies [header.stamp.sec], [header.stamp.nsec] and then
    [twist.linear.x] ([read_leaves], in the order of [leaves]); the
    mutant keeps the last copy only, so the command's stamp stays zero. *)
Definition m_stamp_source_not_copied : program :=
  Mutants.on_def (callback_name "landshark_gps_velocity") (Mutants.on_body (Mutants.on_seq (skipn 2))) copied_prog.
Theorem m_stamp_source_not_copied_refuted: ~ node_ddc copied m_stamp_source_not_copied.
Proof. apply (crefute _ 1). vm_compute. reflexivity. Qed.

Example gps_callback_copies_stamp:
  match find_def copied_prog (callback_name "landshark_gps_velocity") with
  | Some (Gfun (Internal f)) => length (Mutants.unseq (fn_body f))
  | _ => O
  end = 3%nat.
Proof. vm_compute. reflexivity. Qed.

