(** * Systems: a link instance and the system mutation catalogue *)

(** Two LandShark nodes in a cascade: the follower [B]'s left-wheel
    input is remapped onto the leader [A]'s published base velocity
    (its graph function [g_follower] renames the topic).  The link
    [Out1 -> twist.linear.x] of [A] to [twist.linear.x -> In1] of [B] is
    decided by [System.link_ok] and proved, from the two nodes' T2
    ([Loopproof.generate_node_ddc]), as [System.link_holds].  The
    system mutants, each a wiring mistake a system's file could carry,
    are refused: [link_ok] computes [false], so the system's file cannot
    prove its link theorem ([system_link] needs [link_ok = true]). *)

From Coq Require Import String List ZArith.
From ROSGen Require Import Errors Syntax NodeModel Generator DDC Loopproof System.
From ROSGenTests Require Import LandShark.
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
