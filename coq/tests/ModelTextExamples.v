(** * The model text printed by Coq ([ModelText.print_model]) *)

(** The LandShark node's model ([LandShark.landshark]) as canonical text:
    what [pyrosgen generate] compares with its reading of
    examples/landshark/landshark_controller.yaml, and what
    [print_program.sh] writes to [PREFIX.model]. *)

From Coq Require Import String List ZArith.
From ROSGen Require Import Printer NodeModel Wellformed ModelText.
From ROSGenTests Require Import LandShark.
Import ListNotations.
Local Open Scope string_scope.

Definition landshark_lines : list string := [
  "pyrosgen-model 1";
  "node landshark_controller";
  "period_ms 20";
  "controller Controller";
  "inputs Controller_U ExtU_Controller_T";
  "input In1 float64";
  "input In2 float64";
  "input In3 float64";
  "outputs Controller_Y ExtY_Controller_T";
  "output Out1 float64";
  "message ros_time";
  "field sec uint32";
  "field nsec uint32";
  "message std_msgs_Header";
  "field seq uint32";
  "field stamp msg ros_time";
  "message geometry_msgs_Vector3";
  "field x float64";
  "field y float64";
  "field z float64";
  "message geometry_msgs_Twist";
  "field linear msg geometry_msgs_Vector3";
  "field angular msg geometry_msgs_Vector3";
  "message geometry_msgs_TwistStamped";
  "field header msg std_msgs_Header";
  "field twist msg geometry_msgs_Twist";
  "topic /landshark/left_wheel_velocity landshark_left_wheel_velocity subscribe geometry_msgs/TwistStamped 1";
  "topic /landshark/right_wheel_velocity landshark_right_wheel_velocity subscribe geometry_msgs/TwistStamped 1";
  "topic /landshark/gps_velocity landshark_gps_velocity subscribe geometry_msgs/TwistStamped 1";
  "topic /landshark_control/base_velocity landshark_control_base_velocity publish geometry_msgs/TwistStamped 1";
  "input_relation landshark_left_wheel_velocity twist.linear.x In1";
  "input_relation landshark_right_wheel_velocity twist.linear.x In2";
  "input_relation landshark_gps_velocity twist.linear.x In3";
  "output_relation Out1 landshark_control_base_velocity twist.linear.x"].

Example landshark_model_lines: model_lines landshark = landshark_lines.
Proof. vm_compute. reflexivity. Qed.

Example landshark_model_text: print_model landshark = concat_lines landshark_lines.
Proof. vm_compute. reflexivity. Qed.

(** Paths: a field is preceded by [.] unless first, an index is [[i]]. *)
Example path_text_example:
  path_text [PField "pose"; PField "covariance"; PIndex 35] = "pose.covariance[35]"
  /\ path_text [PIndex 2; PField "x"] = "[2].x"
  /\ ftype_text (FTarray (FTmsg "geometry_msgs_Point") 4) = "array 4 msg geometry_msgs_Point".
Proof. vm_compute. auto. Qed.

(** No line of the LandShark text contains a line feed: by
    [ModelText.print_model_items], a model with the same text has the same
    topic and relation lines. *)
Example landshark_lines_ok: lines_ok landshark = true.
Proof. vm_compute. reflexivity. Qed.
