(** * The paper's LandShark node (Table 1), shared by the tests *)

(** The LandShark controller node as Coq terms (as the front end emits
    them for examples/landshark/landshark_controller.yaml), and the
    program [generate] computes for it.  Used by [GeneratorExamples] (the
    generated program, refusals) and [DDCTeeth] (the node DDC theorem
    distinguishes this program from a mutant). *)

From Coq Require Import String List ZArith.
From ROSGen Require Import Errors Syntax Values NodeModel Wellformed Generator.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope list_scope.

(** ** Message definitions (carried fields only: [frame_id] is a string) *)

Definition ros_time : msgdef :=
  mkmsgdef "ros_time" [("sec", FTprim Puint32); ("nsec", FTprim Puint32)].
Definition std_msgs_Header : msgdef :=
  mkmsgdef "std_msgs_Header" [("seq", FTprim Puint32); ("stamp", FTmsg "ros_time")].
Definition geometry_msgs_Vector3 : msgdef :=
  mkmsgdef "geometry_msgs_Vector3"
    [("x", FTprim Pfloat64); ("y", FTprim Pfloat64); ("z", FTprim Pfloat64)].
Definition geometry_msgs_Twist : msgdef :=
  mkmsgdef "geometry_msgs_Twist"
    [("linear", FTmsg "geometry_msgs_Vector3"); ("angular", FTmsg "geometry_msgs_Vector3")].
Definition geometry_msgs_TwistStamped : msgdef :=
  mkmsgdef "geometry_msgs_TwistStamped"
    [("header", FTmsg "std_msgs_Header"); ("twist", FTmsg "geometry_msgs_Twist")].

Definition landshark_msgs : list msgdef :=
  [ros_time; std_msgs_Header; geometry_msgs_Vector3; geometry_msgs_Twist;
   geometry_msgs_TwistStamped].

(** ** The node model of Table 1 *)

Definition twist_x : path := [PField "twist"; PField "linear"; PField "x"].

Definition left_wheel : topic :=
  mktopic "/landshark/left_wheel_velocity" "landshark_left_wheel_velocity"
          "geometry_msgs/TwistStamped" Subscribe "geometry_msgs_TwistStamped" 1.
Definition right_wheel : topic :=
  mktopic "/landshark/right_wheel_velocity" "landshark_right_wheel_velocity"
          "geometry_msgs/TwistStamped" Subscribe "geometry_msgs_TwistStamped" 1.
Definition gps : topic :=
  mktopic "/landshark/gps_velocity" "landshark_gps_velocity"
          "geometry_msgs/TwistStamped" Subscribe "geometry_msgs_TwistStamped" 1.
Definition base : topic :=
  mktopic "/landshark_control/base_velocity" "landshark_control_base_velocity"
          "geometry_msgs/TwistStamped" Publish "geometry_msgs_TwistStamped" 1.

Definition landshark : node_model := {|
  nm_name := "landshark_controller";
  nm_period_ms := 20;
  nm_ctrl := "Controller";
  nm_in_var := "Controller_U";
  nm_in_struct := "ExtU_Controller_T";
  nm_inputs := [("In1", FTprim Pfloat64); ("In2", FTprim Pfloat64); ("In3", FTprim Pfloat64)];
  nm_out_var := "Controller_Y";
  nm_out_struct := "ExtY_Controller_T";
  nm_outputs := [("Out1", FTprim Pfloat64)];
  nm_msgs := landshark_msgs;
  nm_topics := [left_wheel; right_wheel; gps; base];
  nm_inrels :=
    [mkinrel "landshark_left_wheel_velocity" twist_x "In1";
     mkinrel "landshark_right_wheel_velocity" twist_x "In2";
     mkinrel "landshark_gps_velocity" twist_x "In3"];
  nm_outrels := [mkoutrel "Out1" "landshark_control_base_velocity" twist_x];
  nm_timeouts := []; nm_fallbacks := []; nm_drels := []; nm_stamps := []; nm_stamp_from := []; nm_strings := []
|}.

(** [m] with its controller inputs, message definitions, freshness
    (rule 4.12), stamps (4.13) and constant strings (4.14) replaced: the
    test models of [Stamps], [Freshness] and [Strings]. *)
Definition reshape (m : node_model) (inputs : list (ident * ftype)) (msgs : list msgdef)
                   (timeouts : list (ident * Z)) (fallbacks : list (ident * val)) (drels : list drel)
                   (stamps : list (ident * path)) (stamp_from : list (ident * (ident * path)))
                   (strings : list (ident * (path * list Z))) : node_model :=
  {| nm_name := nm_name m; nm_period_ms := nm_period_ms m; nm_ctrl := nm_ctrl m;
     nm_in_var := nm_in_var m; nm_in_struct := nm_in_struct m; nm_inputs := inputs;
     nm_out_var := nm_out_var m; nm_out_struct := nm_out_struct m; nm_outputs := nm_outputs m;
     nm_msgs := msgs; nm_topics := nm_topics m; nm_inrels := nm_inrels m; nm_outrels := nm_outrels m;
     nm_timeouts := timeouts; nm_fallbacks := fallbacks; nm_drels := drels;
     nm_stamps := stamps; nm_stamp_from := stamp_from; nm_strings := strings |}.

(** [generate] refuses [m] with the message [msg]. *)
Definition refused (m : node_model) (msg : string) : Prop :=
  match generate m with
  | Error e => string_of_errmsg e = msg
  | OK _ => False
  end.

(** ** The generated program *)

Definition landshark_result : res program := Eval vm_compute in generate landshark.

Definition landshark_prog : program :=
  match landshark_result with OK p => p | Error _ => mkprogram [] [] "" end.

Lemma landshark_generated: generate landshark = OK landshark_prog.
Proof. vm_compute. reflexivity. Qed.
