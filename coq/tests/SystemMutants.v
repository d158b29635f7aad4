(** * Systems: a link instance and the system mutation catalogue *)

(** Two LandShark nodes in a cascade: the follower [B]'s left-wheel
    input is remapped onto the leader [A]'s published base velocity
    (its graph function [g_follower] renames the topic).  The link
    [Out1 -> twist.linear.x] of [A] to [twist.linear.x -> In1] of [B] is
    decided by [System.link_ok] and proved, from the two nodes' T2
    ([Loopproof.generate_node_ddc]), as [System.link_holds].  The
    system mutants, each a wiring mistake a system's file could carry,
    are refused: [link_ok] computes [false], so the system's file cannot
    prove its link theorem ([system_link] needs [link_ok = true]).  And
    they are wrong, not only refused: the last section refutes the
    semantic property of two crossed pairings ([link_holds] is false of
    the programs, on a concrete run of the two nodes where the transport
    assumption holds) and of a remapping to the wrong topic (on the run
    the ROS graph gives, the follower does not receive what the leader
    computed, while the right remapping does). *)

From Coq Require Import String List ZArith.
From ROSGen Require Import Errors Syntax Values Memory Environment Semantics Interp Interpproof NodeModel Generator
  DDC Loopproof System.
From ROSGenTests Require Import LandShark Mutants.
Import ListNotations.
Local Open Scope string_scope.

Definition g_leader (n : string) : string := n.

Definition g_follower (n : string) : string :=
  if string_dec n "/landshark/left_wheel_velocity" then "/landshark_control/base_velocity" else n.

Definition out1 : outrel := mkoutrel "Out1" "landshark_control_base_velocity" twist_x.
Definition in1 : inrel := mkinrel "landshark_left_wheel_velocity" twist_x "In1".

Lemma cascade_ok : link_ok g_leader landshark base out1 g_follower landshark left_wheel in1 = true.
Proof. vm_compute. reflexivity. Qed.

(** The link, proved from the two nodes' T2. *)
Theorem cascade_link : link_holds landshark landshark_prog base out1 landshark landshark_prog left_wheel in1.
Proof.
  exact (system_link _ _ _ _ _ _ _ _ _ _
           (generate_node_ddc landshark landshark_prog landshark_generated)
           (generate_node_ddc landshark landshark_prog landshark_generated) cascade_ok).
Qed.

(** ** The mutants *)

(** 1. Two relations crossed between the nodes: the link pairs [A]'s
    [Out1 -> twist.linear.x] with [B]'s input [In2], which reads the
    right wheel's topic. *)
Definition in2 : inrel := mkinrel "landshark_right_wheel_velocity" twist_x "In2".
Theorem crossed_inputs_refuted : link_ok g_leader landshark base out1 g_follower landshark left_wheel in2 = false.
Proof. vm_compute. reflexivity. Qed.

(** 2. Two relations crossed between the nodes: the follower reads
    [twist.angular.z] where the leader writes [twist.linear.x] (a node
    whose [In1] reads another field of the same topic). *)
Definition twist_z : path := [PField "twist"; PField "angular"; PField "z"].
Definition follower_z : node_model :=
  {| nm_name := nm_name landshark; nm_period_ms := nm_period_ms landshark; nm_ctrl := nm_ctrl landshark;
     nm_in_var := nm_in_var landshark; nm_in_struct := nm_in_struct landshark; nm_inputs := nm_inputs landshark;
     nm_out_var := nm_out_var landshark; nm_out_struct := nm_out_struct landshark;
     nm_outputs := nm_outputs landshark; nm_msgs := nm_msgs landshark; nm_topics := nm_topics landshark;
     nm_inrels := [mkinrel "landshark_left_wheel_velocity" twist_z "In1";
                   mkinrel "landshark_right_wheel_velocity" twist_x "In2";
                   mkinrel "landshark_gps_velocity" twist_x "In3"];
     nm_outrels := nm_outrels landshark; nm_timeouts := nm_timeouts landshark;
     nm_fallbacks := nm_fallbacks landshark; nm_drels := nm_drels landshark; nm_stamps := nm_stamps landshark;
     nm_stamp_from := nm_stamp_from landshark; nm_strings := nm_strings landshark |}.
Definition in1_z : inrel := mkinrel "landshark_left_wheel_velocity" twist_z "In1".
Theorem crossed_fields_refuted : link_ok g_leader landshark base out1 g_follower follower_z left_wheel in1_z = false.
Proof. vm_compute. reflexivity. Qed.

(** 3. A remapping to the wrong topic: the follower's left wheel goes
    to a topic the leader does not publish. *)
Definition g_wrong (n : string) : string :=
  if string_dec n "/landshark/left_wheel_velocity" then "/landshark_control/base_velocty" else n.
Theorem wrong_remap_refuted : link_ok g_leader landshark base out1 g_wrong landshark left_wheel in1 = false.
Proof. vm_compute. reflexivity. Qed.

(** 4. No remapping at all: the follower listens to its own left wheel. *)
Theorem no_remap_refuted : link_ok g_leader landshark base out1 g_leader landshark left_wheel in1 = false.
Proof. vm_compute. reflexivity. Qed.

(** 5. A link from a subscribed topic: [A]'s left wheel is not published. *)
Definition out1_left : outrel := mkoutrel "Out1" "landshark_left_wheel_velocity" twist_x.
Theorem from_subscription_refuted :
  link_ok g_follower landshark left_wheel out1_left g_follower landshark left_wheel in1 = false.
Proof. vm_compute. reflexivity. Qed.

(** ** Wrong wirings refuted on a run *)

(** [c] with its arrivals replaced.  (A context is built here only:
    a field added to [Environment.ros_context] is one more argument,
    [(ctx_... c)], on the [mkctx] line.) *)
Definition with_arrivals {CS : Type} (c : ros_context CS) (arr : nat -> list arrival) : ros_context CS :=
  mkctx arr (ctx_time c) (ctx_init c) (ctx_step c) (ctx_target c).

(** The leader [A] runs one cycle in [Mutants.ctx]: its controller
    computes [Out1 = 4.0], and it publishes [msgA] on its base velocity. *)
Definition runA : option trace := Eval vm_compute in run_trace 2000 landshark_prog ctx 1.
Definition tA : trace := Eval vm_compute in match runA with Some t => t | None => [] end.
Lemma tA_run : run_trace 2000 landshark_prog ctx 1 = Some tA.
Proof. vm_compute. reflexivity. Qed.

(** The events of the first cycle of a one-cycle trace of [m]. *)
Definition first_cycle (m : node_model) (t : trace) : trace := skipn (length (start_events m)) t.

Definition msgA : mval :=
  Eval vm_compute in match published_on (first_cycle landshark tA) (tp_name base) with
                     | Some msg => msg | None => MVscalar Vundef end.

Example leader_computes_four:
  computed (first_cycle landshark tA) out1 = Some four
  /\ published_field (first_cycle landshark tA) (tp_name base) twist_x = Some four.
Proof. vm_compute. split; reflexivity. Qed.

(** The first cycle of a one-cycle run, from T2's decomposition. *)
Lemma one_cycle:
  forall m t (evs : nat -> trace), t = (start_events m ++ concat (map evs (seq 0 1)))%list ->
  evs O = first_cycle m t.
Proof.
  intros m t evs E. subst t. unfold first_cycle. simpl. rewrite app_nil_r.
  rewrite skipn_app, skipn_all, PeanoNat.Nat.sub_diag. reflexivity.
Qed.

(** The follower [B] (a LandShark node too) runs one cycle where its
    left wheel's callback received the leader's message [msgA] (the
    transport assumption holds: ROS delivered it) and its right wheel's
    [1.0]. *)
Definition ctxB : ros_context unit :=
  with_arrivals ctx (fun k => match k with
                              | O => [mkarrival (tp_name left_wheel) msgA 0; mkarrival (tp_name right_wheel) (msg_x one) 0]
                              | _ => []
                              end).

Lemma ctxB_arrivals_wt: arrivals_wt landshark ctxB.
Proof.
  intros k a tp H Htp _. apply mval_typecheck_iff.
  simpl in Htp. destruct Htp as [<-|[<-|[<-|[]]]];
    destruct k as [|k]; simpl in H; try contradiction;
    repeat destruct H as [H|H]; try contradiction; subst a; vm_compute; reflexivity.
Qed.

Lemma ctxB_controller_wt: controller_wt landshark ctxB.
Proof. exact ctx_controller_wt. Qed.

Definition tB : trace := Eval vm_compute in match run_trace 2000 landshark_prog ctxB 1 with Some t => t | None => [] end.
Lemma tB_run : run_trace 2000 landshark_prog ctxB 1 = Some tB.
Proof. vm_compute. reflexivity. Qed.

(** The right pairing holds on this run: [In1] receives [4.0]; [In2]
    receives the right wheel's [1.0]. *)
Example follower_receives:
  received (first_cycle landshark tB) in1 = Some four /\ received (first_cycle landshark tB) in2 = Some one.
Proof. vm_compute. split; reflexivity. Qed.

(** The refutation of a crossed link on the run above: the leader's
    message of cycle 0 was delivered to the follower's left wheel (the
    transport assumption holds), no fallback applies, and the value the
    follower's controller receives ([GB]) is not the one the leader's
    computed ([GA]).  [tB], [tB_run], [wtB], [cwtB]: the follower's trace,
    its run, and its environment's well-typedness facts. *)
Ltac refute_on_run tB tB_run wtB cwtB :=
  let H := fresh "H" in let F := fresh "F" in let TA := fresh "TA" in let TB := fresh "TB" in
  let EA := fresh "EA" in let EB := fresh "EB" in let GA := fresh "GA" in let GB := fresh "GB" in
  intro H;
  destruct (H unit ctx 1%nat tA unit ctxB 1%nat tB ctx_arrivals_wt ctx_controller_wt wtB cwtB
              (run_trace_sound _ _ _ _ _ _ tA_run) (run_trace_sound _ _ _ _ _ _ tB_run))
    as (sA & evsA & sB & evsB & _ & TA & _ & TB & F);
  apply one_cycle in TA; apply one_cycle in TB;
  destruct (F O O (le_n 1) (le_n 1)) as (uA & yA & restA & uB & yB & restB & v & EA & _ & EB & GA & GB);
  [ exists (mkarrival (tp_name left_wheel) msgA 0); split; [vm_compute; reflexivity|];
    rewrite TA; vm_compute; right; left; reflexivity
  | left; reflexivity
  | rewrite TA in EA; rewrite TB in EB; vm_compute in EA, EB;
    inversion EA; subst; inversion EB; subst;
    vm_compute in GA; vm_compute in GB; rewrite <- GA in GB; discriminate ].

(** 1'. The crossed link is false of the nodes' programs: in the runs
    above, the transport delivered the leader's message of cycle 0 to
    the follower's left wheel, no fallback applies, and the follower's
    [In2] holds [1.0], not the [4.0] the leader computed. *)
Theorem crossed_inputs_run_refuted :
  ~ link_holds landshark landshark_prog base out1 landshark landshark_prog left_wheel in2.
Proof. refute_on_run tB tB_run ctxB_arrivals_wt ctxB_controller_wt. Qed.

(** 2'. The crossed fields are false of the programs: [follower_z]
    (its program generated from its model), in the same run, receives
    on [In1] the leader message's [twist.angular.z], [0.0], not the
    [4.0] the leader computed (which it wrote to [twist.linear.x]). *)
Definition follower_z_prog : program :=
  Eval vm_compute in match generate follower_z with OK p => p | Error _ => mkprogram [] [] "" end.
Lemma follower_z_generated : generate follower_z = OK follower_z_prog.
Proof. vm_compute. reflexivity. Qed.

Lemma ctxB_arrivals_wt_z: arrivals_wt follower_z ctxB.
Proof.
  intros k a tp H Htp _. apply mval_typecheck_iff.
  simpl in Htp. destruct Htp as [<-|[<-|[<-|[]]]];
    destruct k as [|k]; simpl in H; try contradiction;
    repeat destruct H as [H|H]; try contradiction; subst a; vm_compute; reflexivity.
Qed.

Lemma ctxB_controller_wt_z: controller_wt follower_z ctxB.
Proof. intros s u. apply mval_typecheck_iff. vm_compute. reflexivity. Qed.

Definition tBz : trace := Eval vm_compute in match run_trace 2000 follower_z_prog ctxB 1 with Some t => t | None => [] end.
Lemma tBz_run : run_trace 2000 follower_z_prog ctxB 1 = Some tBz.
Proof. vm_compute. reflexivity. Qed.

Theorem crossed_fields_run_refuted :
  ~ link_holds landshark landshark_prog base out1 follower_z follower_z_prog left_wheel in1_z.
Proof. refute_on_run tBz tBz_run ctxB_arrivals_wt_z ctxB_controller_wt_z. Qed.

(** *** A remapping to the wrong topic *)

(** A link's property says nothing of names: the transport assumption
    is its premise.  What a remapping decides is what ROS delivers.
    [wired gA gB mA tpA tpB t others] is the follower's environment
    that the ROS graph gives when the leader's run is [t]: in spin 0,
    the message the leader published on [tpA] in its cycle arrives on
    the follower's [tpB] if the two names resolve (by [gA], [gB]) to one
    graph topic, and not otherwise; [others] arrive as well. *)
Definition wired (gA gB : string -> string) (mA : node_model) (tpA tpB : topic) (t : trace) (others : list arrival)
  : nat -> list arrival :=
  fun k => match k with
           | O => ((if String.eqb (gA (tp_name tpA)) (gB (tp_name tpB)) then
                      match published_on (first_cycle mA t) (tp_name tpA) with
                      | Some msg => [mkarrival (tp_name tpB) msg 0]
                      | None => []
                      end
                    else []) ++ others)%list
           | _ => []
           end.

(** The link's end-to-end property over the wiring: for the runs of one
    cycle of the leader in [Mutants.ctx] and of the follower in the
    environment the graph gives, the follower's controller receives on
    [ir] what the leader's controller computed on [o]. *)
Definition wired_link_holds (gA gB : string -> string) (mA : node_model) (pA : program) (tpA : topic) (o : outrel)
                            (mB : node_model) (pB : program) (tpB : topic) (ir : inrel) (others : list arrival) : Prop :=
  forall tA' tB', program_behaves pA ctx 1 tA' ->
  program_behaves pB (with_arrivals ctx (wired gA gB mA tpA tpB tA' others)) 1 tB' ->
  exists v, computed (first_cycle mA tA') o = Some v /\ received (first_cycle mB tB') ir = Some v.

Definition right_one : list arrival := [mkarrival (tp_name right_wheel) (msg_x one) 0].

(** The right remapping has it (on this run). *)
Definition tW : trace :=
  Eval vm_compute in
    match run_trace 2000 landshark_prog (with_arrivals ctx (wired g_leader g_follower landshark base left_wheel tA right_one)) 1
    with Some t => t | None => [] end.
Lemma tW_run :
  run_trace 2000 landshark_prog (with_arrivals ctx (wired g_leader g_follower landshark base left_wheel tA right_one)) 1
  = Some tW.
Proof. vm_compute. reflexivity. Qed.

Theorem cascade_wired : wired_link_holds g_leader g_follower landshark landshark_prog base out1
                                          landshark landshark_prog left_wheel in1 right_one.
Proof.
  intros tA' tB' BA BB.
  rewrite (run_trace_exact _ _ _ _ _ _ _ tA_run BA) in BB |- *.
  rewrite (run_trace_exact _ _ _ _ _ _ _ tW_run BB).
  exists four. vm_compute. split; reflexivity.
Qed.

(** 3'. The wrong remapping does not: the follower's left wheel listens
    to a topic nobody publishes, its [In1] stays [0.0]. *)
Definition tX : trace :=
  Eval vm_compute in
    match run_trace 2000 landshark_prog (with_arrivals ctx (wired g_leader g_wrong landshark base left_wheel tA right_one)) 1
    with Some t => t | None => [] end.
Lemma tX_run :
  run_trace 2000 landshark_prog (with_arrivals ctx (wired g_leader g_wrong landshark base left_wheel tA right_one)) 1
  = Some tX.
Proof. vm_compute. reflexivity. Qed.

Theorem wrong_remap_run_refuted :
  ~ wired_link_holds g_leader g_wrong landshark landshark_prog base out1 landshark landshark_prog left_wheel in1 right_one.
Proof.
  intro H. destruct (H tA tX (run_trace_sound _ _ _ _ _ _ tA_run) (run_trace_sound _ _ _ _ _ _ tX_run)) as (v & GA & GB).
  vm_compute in GA. vm_compute in GB. rewrite <- GA in GB. discriminate.
Qed.
