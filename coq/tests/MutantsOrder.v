(** * The mutation catalogue, continued: publishing in another order *)

(** LandShark publishes on one topic only, so the mutation "the loop
    publishes its topics in another order than the model's" needs a node
    with two published topics: [landshark2] is LandShark with a second
    output [Out2] related to [twist.linear.x] of a second published topic
    [/landshark_control/base_velocity2].  The program [generate] computes
    for it publishes [base] then [base2] in each cycle, as T2 requires;
    the mutant publishes [base2] first.  As in [Mutants], the mutant is
    run by the interpreter in one concrete well-typed environment, and
    the computable necessary condition [run_okb] of [run_ok] refutes it,
    so [~ node_ddc landshark2 m_publish_order] is proved; the unmutated
    program passes the same check. *)

From Coq Require Import String List ZArith Bool.
From ROSGen Require Import Errors Syntax Values Memory Environment Semantics Interp Interpproof.
From ROSGen Require Import FloatBits NodeModel Wellformed Generator DDC.
From ROSGenTests Require Import LandShark Mutants.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope list_scope.

(** ** The node *)

Definition base2 : topic :=
  mktopic "/landshark_control/base_velocity2" "landshark_control_base_velocity2"
          "geometry_msgs/TwistStamped" Publish "geometry_msgs_TwistStamped" 1.

Definition landshark2 : node_model := {|
  nm_name := "landshark_controller";
  nm_period_ms := 20;
  nm_ctrl := "Controller";
  nm_in_var := "Controller_U";
  nm_in_struct := "ExtU_Controller_T";
  nm_inputs := [("In1", FTprim Pfloat64); ("In2", FTprim Pfloat64); ("In3", FTprim Pfloat64)];
  nm_out_var := "Controller_Y";
  nm_out_struct := "ExtY_Controller_T";
  nm_outputs := [("Out1", FTprim Pfloat64); ("Out2", FTprim Pfloat64)];
  nm_msgs := landshark_msgs;
  nm_topics := [left_wheel; right_wheel; gps; base; base2];
  nm_inrels :=
    [mkinrel "landshark_left_wheel_velocity" twist_x "In1";
     mkinrel "landshark_right_wheel_velocity" twist_x "In2";
     mkinrel "landshark_gps_velocity" twist_x "In3"];
  nm_outrels := [mkoutrel "Out1" "landshark_control_base_velocity" twist_x;
                 mkoutrel "Out2" "landshark_control_base_velocity2" twist_x];
  nm_timeouts := []; nm_fallbacks := []; nm_drels := []; nm_stamps := []; nm_stamp_from := []; nm_strings := []
|}.

Definition landshark2_result : res program := Eval vm_compute in generate landshark2.

Definition landshark2_prog : program :=
  match landshark2_result with OK p => p | Error _ => mkprogram [] [] "" end.

Lemma landshark2_generated: generate landshark2 = OK landshark2_prog.
Proof. vm_compute. reflexivity. Qed.

(** ** The environment: the controller outputs [Out1 = 4.0], [Out2 = 5.0] *)

Definition ctx2 : ros_context unit :=
  mkctx (fun k => match k with
                  | O => [mkarrival (tp_name left_wheel) (msg_x one) 0;
                          mkarrival (tp_name right_wheel) (msg_x two) 0;
                          mkarrival (tp_name gps) (msg_x three) 0]
                  | _ => []
                  end)
        (fun _ => 0%Z) tt (fun _ _ => (tt, MVstruct [("Out1", MVscalar four); ("Out2", MVscalar five)])) Ros1.

Lemma ctx2_arrivals_wt: arrivals_wt landshark2 ctx2.
Proof.
  intros k a tp H Htp _. apply mval_typecheck_iff.
  simpl in Htp. destruct Htp as [<-|[<-|[<-|[]]]];
    destruct k as [|k]; simpl in H; try contradiction;
    repeat destruct H as [H|H]; try contradiction; subst a; vm_compute; reflexivity.
Qed.

Lemma ctx2_controller_wt: controller_wt landshark2 ctx2.
Proof. intros s u. apply mval_typecheck_iff. vm_compute. reflexivity. Qed.

Definition check2 : program -> nat -> bool := check_in landshark2 ctx2 2000.

Lemma refute2: forall p n, check2 p n = false -> ~ node_ddc landshark2 p.
Proof. exact (refute_in landshark2 ctx2 2000 ctx2_arrivals_wt ctx2_controller_wt). Qed.

(** The generated program passes (as T2 says it must). *)
Example p2_passes: check2 landshark2_prog 0 = true /\ check2 landshark2_prog 1 = true
                   /\ check2 landshark2_prog 2 = true.
Proof. vm_compute. auto. Qed.

(** ** (o) Publishing in another order *)

(** Positions in [loop]'s body: 0-4 as in [Mutants], then 5
    [output_glue_base(&cmd)], 6 [ros_publish_base(&cmd)], 7
    [output_glue_base2(&cmd2)], 8 [ros_publish_base2(&cmd2)], 9
    [ros_rate_sleep()].  The mutant moves 7-8 before 5-6. *)
Definition publish_second_first (l : list statement) : list statement :=
  firstn 5 l ++ firstn 2 (skipn 7 l) ++ firstn 2 (skipn 5 l) ++ skipn 9 l.

Definition m_publish_order : program :=
  on_def loop_name (on_body (on_loop publish_second_first)) landshark2_prog.

(** The mutant is a different program, with the same statements. *)
Example publish_order_is_a_permutation:
  m_publish_order <> landshark2_prog.
Proof. vm_compute. discriminate. Qed.

Theorem publish_order_refuted: ~ node_ddc landshark2 m_publish_order.
Proof. apply (refute2 _ 1). vm_compute. reflexivity. Qed.
