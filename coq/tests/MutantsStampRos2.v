(** * ROS 2 stamps (rules 4.13, 4.17): the generator, the interpreter, and mutants *)

(** The LandShark node read with ROS 2's message definitions
    ([builtin_interfaces/Time] is [int32 sec], [uint32 nanosec];
    [std_msgs/Header] has no [seq]), its published [TwistStamped] stamped
    with the cycle's ROS time: [generate] accepts it and stores the
    seconds as [(int)_t_uint]; the interpreter runs it in an environment
    whose second cycle is read past 2038 (3,000,000,000 s), and the
    published [sec] is the signed 32-bit reading of the seconds,
    wrapped modulo 2^32 (-1,294,967,296), as T2 says
    ([DDC.stamp_sec]); two mutants of the stamp code (the seconds and
    nanoseconds swapped, the seconds saturated at 2^31 - 1 instead of
    wrapped) are refuted against T2.  A stamp copied from a subscribed
    topic copies a negative [sec] and the [nanosec] unchanged. *)

From Coq Require Import String List ZArith Lia.
From ROSGen Require Import Errors Syntax Values Memory Environment Semantics Interp Interpproof
  NodeModel Wellformed Generator Generatorspec DDC Loopproof.
From ROSGenTests Require Import LandShark.
From ROSGenTests Require Stamps.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope list_scope.

(** ** The model, as the ROS 2 front end emits it *)

Definition builtin_interfaces_Time : msgdef :=
  mkmsgdef "builtin_interfaces_Time" [("sec", FTprim Pint32); ("nanosec", FTprim Puint32)].
Definition std_msgs_Header2 : msgdef :=
  mkmsgdef "std_msgs_Header" [("stamp", FTmsg "builtin_interfaces_Time")].
Definition ros2_msgs : list msgdef :=
  [builtin_interfaces_Time; std_msgs_Header2; geometry_msgs_Vector3; geometry_msgs_Twist;
   geometry_msgs_TwistStamped].

Definition header_stamp : path := Stamps.header_stamp.

Definition stamped2 : node_model :=
  reshape landshark (nm_inputs landshark) ros2_msgs [] [] [] [("landshark_control_base_velocity", header_stamp)]
          [] [].

Example stamped2_wf: wf stamped2 = true /\ time_is_ros2 (nm_msgs stamped2) = true.
Proof. vm_compute. split; reflexivity. Qed.

Definition stamped2_result : res program := Eval vm_compute in generate stamped2.
Definition stamped2_prog : program :=
  Eval vm_compute in match stamped2_result with OK p => p | Error _ => mkprogram [] [] "" end.

Lemma stamped2_generates: generate stamped2 = OK stamped2_prog.
Proof. vm_compute. reflexivity. Qed.

(** ROS 1's [time] in a ROS 2 header, or a time message of another
    shape, is refused. *)
Example refuse_ros1_stamp_in_ros2_model:
  refused (reshape landshark (nm_inputs landshark)
             [builtin_interfaces_Time; mkmsgdef "ros_time" [("sec", FTprim Puint32); ("nsec", FTprim Puint32)];
              std_msgs_Header2; geometry_msgs_Vector3; geometry_msgs_Twist; geometry_msgs_TwistStamped]
             [] [] [] [("landshark_control_base_velocity", header_stamp)] [] [])
    "Generator: bad stamp (rule 4.13) on topic 'landshark_control_base_velocity': '.header.stamp' must be a time field of a published message that no output relation writes".
Proof. vm_compute. reflexivity. Qed.

Example refuse_unsigned_ros2_sec:
  refused (reshape landshark (nm_inputs landshark)
             [mkmsgdef "builtin_interfaces_Time" [("sec", FTprim Puint32); ("nanosec", FTprim Puint32)];
              std_msgs_Header2; geometry_msgs_Vector3; geometry_msgs_Twist; geometry_msgs_TwistStamped]
             [] [] [] [("landshark_control_base_velocity", header_stamp)] [] [])
    "Generator: stamps need the message ros_time with the uint32 fields sec and nsec (ROS 2: builtin_interfaces_Time with the int32 sec and the uint32 nanosec)".
Proof. vm_compute. reflexivity. Qed.

(** ** A run with known times *)

(** Cycle 1 is read at 1 s + 250 ms, cycle 2 at 3,000,000,000 s + 7 ns
    (past 2038: the seconds do not fit an [int32]). *)
Definition clock (k : nat) : Z :=
  match k with
  | 2%nat => 3000000000000000007
  | _ => Z.of_nat k * 1000000000 + 250000000
  end.

Definition ctx : ros_context unit :=
  mkctx (fun _ => []) clock tt (fun _ _ => (tt, Stamps.y_one)) Ros2.

Lemma ctx_arrivals_wt: arrivals_wt stamped2 ctx.
Proof. intros k a tp H. simpl in H. contradiction. Qed.

Lemma ctx_controller_wt: controller_wt stamped2 ctx.
Proof. intros s u. apply mval_typecheck_iff. vm_compute. reflexivity. Qed.

Definition int_at := Stamps.int_at.

(** The stamps ([sec], [nanosec]) of the published messages of a trace. *)
Definition stamps_of (t : trace) : list (option Z * option Z) :=
  flat_map (fun e => match e with
                     | Epublish _ mv => [(int_at mv (header_stamp ++ [PField "sec"])%list,
                                          int_at mv (header_stamp ++ [PField "nanosec"])%list)]
                     | _ => []
                     end) t.

(** Two cycles: stamps (1 s, 250 ms) and (-1,294,967,296 s, 7 ns): the
    seconds 3,000,000,000 wrapped to a signed 32-bit number. *)
Example stamped2_run:
  match run_trace 2000 stamped2_prog ctx 2 with
  | Some t => stamps_of t = [(Some 1%Z, Some 250000000%Z); (Some (-1294967296)%Z, Some 7%Z)]
  | None => False
  end.
Proof. vm_compute. reflexivity. Qed.

(** ** Mutants *)

(** What T2 says of the stamps of a run of [n] cycles of this node: the
    [i]-th publication carries the time of cycle [i], its seconds read
    as a signed 32-bit number. *)
Definition stamps_expected (n : nat) : list (option Z * option Z) :=
  map (fun i => (Some (norm_int I32 Signed (time_sec (clock (S i)))), Some (time_nsec (clock (S i))))) (seq 0 n).

Lemma stamps_of_app: forall t1 t2 : trace, stamps_of (t1 ++ t2)%list = (stamps_of t1 ++ stamps_of t2)%list.
Proof. intros; unfold stamps_of; apply flat_map_app. Qed.

Lemma int_at_sent_stamp:
  forall m (u y : mval) tp mv s1 s2,
  published m = [tp] ->
  mval_has_type (composites m) (Tstruct (tp_msg tp)) mv ->
  unbounded_path (composites m) (Tstruct (tp_msg tp)) (path_steps (header_stamp ++ [PField "sec"])) = true ->
  unbounded_path (composites m) (Tstruct (tp_msg tp)) (path_steps (header_stamp ++ [PField "nanosec"])) = true ->
  type_at (composites m) (Tstruct (tp_msg tp)) (path_steps (header_stamp ++ [PField "sec"])) = Some (Tint I32 s1) ->
  type_at (composites m) (Tstruct (tp_msg tp)) (path_steps (header_stamp ++ [PField "nanosec"])) = Some (Tint I32 s2) ->
  stamps_of (Estep u y :: publish_events m (published m) [mv] ++ [Esleep (nm_period_ms m)])
  = [(int_at mv (header_stamp ++ [PField "sec"]), int_at mv (header_stamp ++ [PField "nanosec"]))].
Proof.
  intros m u y tp mv s1 s2 Pm T U1 U2 Ty1 Ty2.
  destruct (mval_get_has_type _ _ _ _ _ T Ty1) as (x1 & Gs & Tx1). inversion Tx1; subst; try discriminate.
  destruct (mval_get_has_type _ _ _ _ _ T Ty2) as (x2 & Gn & Tx2). inversion Tx2; subst; try discriminate.
  rewrite Pm. unfold stamps_of, publish_events. cbn [map combine fst snd flat_map app].
  exact (f_equal (fun a => [a]) (f_equal2 pair (Stamps.int_at_sent m tp mv _ _ _ T U1 Ty1 Gs)
                                               (Stamps.int_at_sent m tp mv _ _ _ T U2 Ty2 Gn))).
Qed.

Lemma run_ok_stamps:
  forall n t, run_ok stamped2 ctx n t -> stamps_of t = stamps_expected n.
Proof.
  intros n t (s & evs & _ & -> & C).
  rewrite stamps_of_app. replace (stamps_of (start_events stamped2)) with (@nil (option Z * option Z))
    by (vm_compute; reflexivity).
  simpl app. unfold stamps_expected.
  assert (G: forall k, (k <= n)%nat ->
             stamps_of (concat (map evs (seq (n - k) k)))
             = map (fun i => (Some (norm_int I32 Signed (time_sec (clock (S i)))), Some (time_nsec (clock (S i)))))
                   (seq (n - k) k)).
  { induction k as [|k IH]; intros Hk; simpl; auto.
    rewrite stamps_of_app.
    destruct (C (n - S k)%nat ltac:(lia)) as (u & y & mvs & E & _ & _ & PV).
    rewrite E. simpl published in PV.
    inversion PV as [|tp mv tps mvs' P F]; subst. inversion F; subst.
    destruct P as (T & _ & ST & _).
    destruct (ST header_stamp eq_refl) as [Gs Gn].
    assert (R2: time_is_ros2 (nm_msgs stamped2) = true) by (vm_compute; reflexivity).
    unfold stamp_sec, stamp_nsec, time_nsec_field in Gs, Gn. rewrite R2 in Gs, Gn.
    rewrite (int_at_sent_stamp stamped2 u y base mv Signed Unsigned eq_refl T
               ltac:(vm_compute; reflexivity) ltac:(vm_compute; reflexivity)
               ltac:(vm_compute; reflexivity) ltac:(vm_compute; reflexivity)).
    simpl in Gs, Gn. simpl. unfold int_at, Stamps.int_at. simpl. rewrite Gs, Gn. f_equal.
    replace (S (n - S k)) with (n - k)%nat by lia. apply IH. lia. }
  specialize (G n (le_n n)). rewrite Nat.sub_diag in G. exact G.
Qed.

Definition check (p : program) (n : nat) : bool :=
  match run_trace 2000 p ctx n with
  | Some t => if list_eq_dec Stamps.stamp_eq_dec (stamps_of t) (stamps_expected n) then true else false
  | None => true
  end.

Lemma refute: forall p n, check p n = false -> ~ node_ddc stamped2 p.
Proof.
  intros p n H D. unfold check in H.
  destruct (run_trace 2000 p ctx n) as [t|] eqn:R; [|discriminate].
  destruct (D unit ctx n ctx_arrivals_wt ctx_controller_wt) as [_ All].
  rewrite (run_ok_stamps n t (All t (run_trace_sound _ ctx 2000 p n t R))) in H.
  destruct (list_eq_dec Stamps.stamp_eq_dec (stamps_expected n) (stamps_expected n)); congruence.
Qed.

(** The generated program passes (as T2 says it must). *)
Example stamped2_passes: check stamped2_prog 2 = true.
Proof. vm_compute. reflexivity. Qed.

(** (r1) the seconds and nanoseconds swapped: [sec = (int)ros_time_nsec()],
    [nanosec = ros_time_sec()] *)
Definition m_ros2_stamp_swapped : program :=
  Stamps.on_output_glue (fun b => match b with
                                  | Ssequence (Ssequence base st) strs => Ssequence (Ssequence base (Stamps.swap_time st)) strs
                                  | _ => b
                                  end) stamped2_prog.
Theorem m_ros2_stamp_swapped_refuted: ~ node_ddc stamped2 m_ros2_stamp_swapped.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** [d = (int)e;] made [if (e > 2147483647) d = 2147483647; else d = (int)e;]. *)
Fixpoint saturate (s : statement) : statement :=
  match s with
  | Ssequence a b => Ssequence (saturate a) (saturate b)
  | Sassign d (Ecast e (Tint I32 Signed)) =>
      Sifthenelse (Ebinop Ogt e (Econst_int 2147483647 (Tint I32 Unsigned)) (Tint I32 Signed))
                  (Sassign d (Econst_int 2147483647 (Tint I32 Signed)))
                  (Sassign d (Ecast e (Tint I32 Signed)))
  | _ => s
  end.

(** (r2) the unsigned seconds stored into the [int32] saturated at
    2^31 - 1 instead of wrapped modulo 2^32: right until 2038, wrong
    after (the second cycle) *)
Definition m_ros2_stamp_saturated : program :=
  Stamps.on_output_glue (fun b => match b with
                                  | Ssequence (Ssequence base st) strs => Ssequence (Ssequence base (saturate st)) strs
                                  | _ => b
                                  end) stamped2_prog.
Example m_ros2_stamp_saturated_first_cycle_right: check m_ros2_stamp_saturated 1 = true.
Proof. vm_compute. reflexivity. Qed.
Theorem m_ros2_stamp_saturated_refuted: ~ node_ddc stamped2 m_ros2_stamp_saturated.
Proof. apply (refute _ 2). vm_compute. reflexivity. Qed.

(** ** A stamp copied from a subscribed topic *)

(** [copied2]: the command carries the [header.stamp] of the newest GPS
    message: [sec] copied as an [int32] (through [_t_int]), [nanosec] as
    a [uint32]. *)
Definition copied2 : node_model :=
  reshape landshark (nm_inputs landshark) ros2_msgs [] [] [] [("landshark_control_base_velocity", header_stamp)]
          [("landshark_control_base_velocity", ("landshark_gps_velocity", header_stamp))] [].

Definition copied2_result : res program := Eval vm_compute in generate copied2.
Definition copied2_prog : program :=
  Eval vm_compute in match copied2_result with OK p => p | Error _ => mkprogram [] [] "" end.

Lemma copied2_generates: generate copied2 = OK copied2_prog.
Proof. vm_compute. reflexivity. Qed.

Definition TS : type := Tstruct "geometry_msgs_TwistStamped".

(** A GPS message stamped (-5 s, 7 ns). *)
Definition gps_msg : mval :=
  match mval_set (zero_mval (composites copied2) TS) (path_steps (header_stamp ++ [PField "sec"])) (MVscalar (Vint (-5))) with
  | Some v => match mval_set v (path_steps (header_stamp ++ [PField "nanosec"])) (MVscalar (Vint 7)) with
              | Some v' => v'
              | None => MVscalar Vundef
              end
  | None => MVscalar Vundef
  end.

Definition cctx : ros_context unit :=
  mkctx (fun k => match k with
                  | 1%nat => [mkarrival (tp_name gps) gps_msg 7]
                  | _ => []
                  end)
        clock tt (fun _ _ => (tt, Stamps.y_one)) Ros2.

(** Zero before the first GPS message, then its stamp, negative [sec]
    and all. *)
Example copied2_run:
  match run_trace 2000 copied2_prog cctx 2 with
  | Some t => stamps_of t = [(Some 0%Z, Some 0%Z); (Some (-5)%Z, Some 7%Z)]
  | None => False
  end.
Proof. vm_compute. reflexivity. Qed.
