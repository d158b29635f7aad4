(** * The generator on the paper's LandShark node (Table 1) *)

(** The LandShark controller node ([LandShark]: the model as Coq terms),
    the program [generate] computes for it, and well-formedness
    violations that [generate] must refuse with a message naming the
    culprit.  Every [Example] is checked by [vm_compute]. *)

From Coq Require Import String List ZArith.
From ROSGen Require Import Errors Syntax NodeModel Wellformed Generator Generatorspec Generatorproof Assignproof.
From ROSGenTests Require Import LandShark.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope list_scope.

(** ** The generated program *)

Example landshark_wf: wf landshark = true.
Proof. vm_compute. reflexivity. Qed.

Example landshark_generates: landshark_result = OK landshark_prog.
Proof. vm_compute. reflexivity. Qed.

(** The leaves of [TwistStamped]: 3 integers, then 6 doubles. *)
Example landshark_leaves:
  leaves landshark_msgs "geometry_msgs_TwistStamped" =
  [([PField "header"; PField "seq"], Puint32);
   ([PField "header"; PField "stamp"; PField "sec"], Puint32);
   ([PField "header"; PField "stamp"; PField "nsec"], Puint32);
   ([PField "twist"; PField "linear"; PField "x"], Pfloat64);
   ([PField "twist"; PField "linear"; PField "y"], Pfloat64);
   ([PField "twist"; PField "linear"; PField "z"], Pfloat64);
   ([PField "twist"; PField "angular"; PField "x"], Pfloat64);
   ([PField "twist"; PField "angular"; PField "y"], Pfloat64);
   ([PField "twist"; PField "angular"; PField "z"], Pfloat64)].
Proof. vm_compute. reflexivity. Qed.

(** The body of an internal function of the program, [Sskip] if none. *)
Definition body_of (p : program) (id : ident) : statement :=
  match find_def p id with Some (Gfun (Internal f)) => fn_body f | _ => Sskip end.

Definition temps_of_fn (p : program) (id : ident) : list (ident * type) :=
  match find_def p id with Some (Gfun (Internal f)) => fn_temps f | _ => [] end.

(** Number of [Sset] / [Sassign] in a statement. *)
Fixpoint count_sets (s : statement) : nat :=
  match s with
  | Sset _ _ => 1
  | Ssequence s1 s2 | Sifthenelse _ s1 s2 => count_sets s1 + count_sets s2
  | Sloop s1 => count_sets s1
  | _ => 0
  end.

Definition count_assigns (s : statement) : nat := length (assigned_places s).

(** The callback of the left wheel copies the one leaf that the node
    reads of it ([twist.linear.x], Figure 11) through one temporary, into
    the global message; the eight other leaves of [TwistStamped] are not
    copied. *)
Example callback_copies:
  count_sets (body_of landshark_prog "landshark_left_wheel_velocity_callback") = 1%nat
  /\ count_assigns (body_of landshark_prog "landshark_left_wheel_velocity_callback") = 1%nat.
Proof. vm_compute. split; reflexivity. Qed.

Example callback_places:
  assigned_places (body_of landshark_prog "landshark_left_wheel_velocity_callback") =
  [Some (Rvar "landshark_left_wheel_velocity_msg", [PField "twist"; PField "linear"; PField "x"])].
Proof. vm_compute. reflexivity. Qed.

Example callback_reads:
  read_paths landshark "landshark_left_wheel_velocity" = [[PField "twist"; PField "linear"; PField "x"]]
  /\ filter (fun l => negb (is_read landshark "landshark_left_wheel_velocity" (fst l)))
            (leaves landshark_msgs "geometry_msgs_TwistStamped") <> [].
Proof. vm_compute. split; [reflexivity|discriminate]. Qed.

Example callback_temps:
  temps_of_fn landshark_prog "landshark_gps_velocity_callback" =
  [("_t_double", Tfloat F64)].
Proof. vm_compute. reflexivity. Qed.

(** [input_glue] is exactly Figure 8. *)
Definition TS : type := Tstruct "geometry_msgs_TwistStamped".

Definition twist_x_of (e : expr) : expr :=
  Efield (Efield (Efield e "twist" (Tstruct "geometry_msgs_Twist"))
                 "linear" (Tstruct "geometry_msgs_Vector3"))
         "x" tdouble.

Definition input_copy_of (g In : ident) : statement :=
  Ssequence (Sset "_t_double" (twist_x_of (Evar g TS)))
            (Sassign (Efield (Evar "Controller_U" (Tstruct "ExtU_Controller_T")) In tdouble)
                     (Etempvar "_t_double" tdouble)).

Definition expected_input_glue : function :=
  mkfunction Tvoid [] [] [("_t_double", tdouble)]
    (Ssequence (input_copy_of "landshark_left_wheel_velocity_msg" "In1")
    (Ssequence (input_copy_of "landshark_right_wheel_velocity_msg" "In2")
    (Ssequence (input_copy_of "landshark_gps_velocity_msg" "In3") Sskip))).

Example input_glue_is_figure_8:
  find_def landshark_prog "input_glue" = Some (Gfun (Internal expected_input_glue)).
Proof. vm_compute. reflexivity. Qed.

(** [output_glue]: zero the 9 leaves of [*command], then one copy, then
    no constant string. *)
Definition expected_output_copy : statement :=
  Ssequence (Sset "_t_double" (Efield (Evar "Controller_Y" (Tstruct "ExtY_Controller_T")) "Out1" tdouble))
            (Sassign (twist_x_of (Ederef (Etempvar "command" (tptr TS)) TS))
                     (Etempvar "_t_double" tdouble)).

Example output_glue_shape:
  match body_of landshark_prog "output_glue_landshark_control_base_velocity" with
  | Ssequence (Ssequence zeros copies) strings =>
      count_assigns zeros = 9%nat /\ copies = Ssequence expected_output_copy Sskip /\ strings = Sskip
  | _ => False
  end.
Proof. vm_compute. repeat split; reflexivity. Qed.

(** [loop]: test, spin, [input_glue], step, output glue, publish, sleep. *)
Example loop_shape:
  body_of landshark_prog "loop" =
  Sloop (seq_of
    [Scall (Some "_ok") (Evar "ros_ok" (Tfunction [] tint)) [];
     Sifthenelse (Etempvar "_ok" tint) Sskip Sbreak;
     call0 "ros_spinOnce";
     call0 "input_glue";
     call0 "Controller_step";
     Scall None (Evar "output_glue_landshark_control_base_velocity" (Tfunction [tptr TS] Tvoid))
           [Eaddrof (Evar "landshark_control_base_velocity_cmd" TS) (tptr TS)];
     Scall None (Evar "ros_publish_landshark_control_base_velocity" (Tfunction [tptr TS] Tvoid))
           [Eaddrof (Evar "landshark_control_base_velocity_cmd" TS) (tptr TS)];
     call0 "ros_rate_sleep"]).
Proof. vm_compute. reflexivity. Qed.

(** The global names, all distinct. *)
Example landshark_globals:
  map fst (prog_defs landshark_prog) =
  ["ros_init"; "ros_ok"; "ros_spinOnce"; "ros_rate_sleep";
   "ros_subscribe_landshark_left_wheel_velocity";
   "ros_subscribe_landshark_right_wheel_velocity";
   "ros_subscribe_landshark_gps_velocity";
   "ros_advertise_landshark_control_base_velocity";
   "ros_publish_landshark_control_base_velocity";
   "Controller_initialize"; "Controller_step"; "Controller_U"; "Controller_Y";
   "landshark_left_wheel_velocity_msg"; "landshark_right_wheel_velocity_msg";
   "landshark_gps_velocity_msg";
   "landshark_left_wheel_velocity_callback"; "landshark_right_wheel_velocity_callback";
   "landshark_gps_velocity_callback";
   "input_glue"; "output_glue_landshark_control_base_velocity"; "loop"; "main"].
Proof. vm_compute. reflexivity. Qed.

(** ** Refused models *)

(** [generate m] fails, and its message, rendered, is [msg]. *)
Definition refused (m : node_model) (msg : string) : Prop :=
  wf m = false /\
  match generate m with
  | Error e => string_of_errmsg e = msg
  | OK _ => False
  end.

Definition with_inrels (m : node_model) (l : list inrel) : node_model :=
  {| nm_name := nm_name m; nm_period_ms := nm_period_ms m; nm_ctrl := nm_ctrl m;
     nm_in_var := nm_in_var m; nm_in_struct := nm_in_struct m; nm_inputs := nm_inputs m;
     nm_out_var := nm_out_var m; nm_out_struct := nm_out_struct m; nm_outputs := nm_outputs m;
     nm_msgs := nm_msgs m; nm_topics := nm_topics m; nm_inrels := l; nm_outrels := nm_outrels m;
  nm_timeouts := []; nm_fallbacks := []; nm_drels := []; nm_stamps := []; nm_stamp_from := []; nm_strings := [] |}.

Definition with_outrels (m : node_model) (l : list outrel) : node_model :=
  {| nm_name := nm_name m; nm_period_ms := nm_period_ms m; nm_ctrl := nm_ctrl m;
     nm_in_var := nm_in_var m; nm_in_struct := nm_in_struct m; nm_inputs := nm_inputs m;
     nm_out_var := nm_out_var m; nm_out_struct := nm_out_struct m; nm_outputs := nm_outputs m;
     nm_msgs := nm_msgs m; nm_topics := nm_topics m; nm_inrels := nm_inrels m; nm_outrels := l;
  nm_timeouts := []; nm_fallbacks := []; nm_drels := []; nm_stamps := []; nm_stamp_from := []; nm_strings := [] |}.

Definition with_inputs (m : node_model) (l : list (ident * ftype)) : node_model :=
  {| nm_name := nm_name m; nm_period_ms := nm_period_ms m; nm_ctrl := nm_ctrl m;
     nm_in_var := nm_in_var m; nm_in_struct := nm_in_struct m; nm_inputs := l;
     nm_out_var := nm_out_var m; nm_out_struct := nm_out_struct m; nm_outputs := nm_outputs m;
     nm_msgs := nm_msgs m; nm_topics := nm_topics m; nm_inrels := nm_inrels m;
     nm_outrels := nm_outrels m;
  nm_timeouts := []; nm_fallbacks := []; nm_drels := []; nm_stamps := []; nm_stamp_from := []; nm_strings := [] |}.

Definition with_topics_msgs (m : node_model) (tps : list topic) (msgs : list msgdef) : node_model :=
  {| nm_name := nm_name m; nm_period_ms := nm_period_ms m; nm_ctrl := nm_ctrl m;
     nm_in_var := nm_in_var m; nm_in_struct := nm_in_struct m; nm_inputs := nm_inputs m;
     nm_out_var := nm_out_var m; nm_out_struct := nm_out_struct m; nm_outputs := nm_outputs m;
     nm_msgs := msgs; nm_topics := tps; nm_inrels := nm_inrels m;
     nm_outrels := nm_outrels m;
  nm_timeouts := []; nm_fallbacks := []; nm_drels := []; nm_stamps := []; nm_stamp_from := []; nm_strings := [] |}.

(** An input fed twice. *)
Example refuse_input_fed_twice:
  refused (with_inrels landshark (nm_inrels landshark ++ [mkinrel "landshark_gps_velocity" twist_x "In1"]))
    "Generator: controller input fed by several input relations: 'In1'".
Proof. vm_compute. split; reflexivity. Qed.

(** An input fed by no relation. *)
Example refuse_input_not_fed:
  refused (with_inrels landshark (firstn 2 (nm_inrels landshark)))
    "Generator: controller input not fed by any input relation: 'In3'".
Proof. vm_compute. split; reflexivity. Qed.

(** [float64] into a [float32] input. *)
Example refuse_float64_to_float32:
  refused (with_inputs landshark [("In1", FTprim Pfloat64); ("In2", FTprim Pfloat64); ("In3", FTprim Pfloat32)])
    "Generator: type mismatch in input relation: 'landshark_gps_velocity.twist.linear.x' is float64 but controller input 'In3' is float32".
Proof. vm_compute. split; reflexivity. Qed.

(** [bool] into a [uint8] input: the same C type, but not the same model
    type.  The same model with a [bool] input is accepted. *)
Definition std_msgs_Bool : msgdef := mkmsgdef "std_msgs_Bool" [("data", FTprim Pbool)].
Definition estop : topic := mktopic "/landshark/estop" "landshark_estop" "std_msgs/Bool" Subscribe "std_msgs_Bool" 1.

Definition with_estop (q : prim) : node_model :=
  with_inrels
    (with_inputs (with_topics_msgs landshark (nm_topics landshark ++ [estop])
                                   (landshark_msgs ++ [std_msgs_Bool]))
                 (nm_inputs landshark ++ [("In4", FTprim q)]))
    (nm_inrels landshark ++ [mkinrel "landshark_estop" [PField "data"] "In4"]).

Example accept_bool_to_bool: wf (with_estop Pbool) = true.
Proof. vm_compute. reflexivity. Qed.

Example refuse_bool_to_uint8:
  refused (with_estop Puint8)
    "Generator: type mismatch in input relation: 'landshark_estop.data' is bool but controller input 'In4' is uint8".
Proof. vm_compute. split; reflexivity. Qed.

(** A field that does not exist. *)
Example refuse_unknown_field:
  refused (with_outrels landshark [mkoutrel "Out1" "landshark_control_base_velocity"
                                            [PField "twist"; PField "linear"; PField "w"]])
    "Generator: output relation: '.twist.linear.w' is not a carried scalar field of message 'geometry_msgs_TwistStamped'".
Proof. vm_compute. split; reflexivity. Qed.

(** A path that stops at a struct. *)
Example refuse_non_scalar_path:
  refused (with_inrels landshark
             [mkinrel "landshark_left_wheel_velocity" [PField "twist"; PField "linear"] "In1";
              mkinrel "landshark_right_wheel_velocity" twist_x "In2";
              mkinrel "landshark_gps_velocity" twist_x "In3"])
    "Generator: input relation: '.twist.linear' is not a carried scalar field of message 'geometry_msgs_TwistStamped'".
Proof. vm_compute. split; reflexivity. Qed.

(** Array indices: [covariance[35]] is accepted, [covariance[36]] is not. *)
Definition geometry_msgs_TwistWithCovariance : msgdef :=
  mkmsgdef "geometry_msgs_TwistWithCovariance"
    [("twist", FTmsg "geometry_msgs_Twist"); ("covariance", FTarray (FTprim Pfloat64) 36)].
Definition odom : topic :=
  mktopic "/landshark/odom_twist" "landshark_odom_twist" "geometry_msgs/TwistWithCovariance" Subscribe "geometry_msgs_TwistWithCovariance" 2.

Definition with_covariance (i : Z) : node_model :=
  with_inrels
    (with_inputs (with_topics_msgs landshark (nm_topics landshark ++ [odom])
                                   (landshark_msgs ++ [geometry_msgs_TwistWithCovariance]))
                 (nm_inputs landshark ++ [("In4", FTprim Pfloat64)]))
    (nm_inrels landshark ++ [mkinrel "landshark_odom_twist" [PField "covariance"; PIndex i] "In4"]).

Example accept_index_35: wf (with_covariance 35) = true.
Proof. vm_compute. reflexivity. Qed.

Example covariance_leaves: length (leaves (nm_msgs (with_covariance 35)) "geometry_msgs_TwistWithCovariance") = 42%nat.
Proof. vm_compute. reflexivity. Qed.

Example refuse_index_36:
  refused (with_covariance 36)
    "Generator: input relation: '.covariance[36]' is not a carried scalar field of message 'geometry_msgs_TwistWithCovariance'".
Proof. vm_compute. split; reflexivity. Qed.

Example refuse_index_negative:
  refused (with_covariance (-1))
    "Generator: input relation: '.covariance[-1]' is not a carried scalar field of message 'geometry_msgs_TwistWithCovariance'".
Proof. vm_compute. split; reflexivity. Qed.

(** A subscribed topic used as an output. *)
Example refuse_output_to_subscribed:
  refused (with_outrels landshark [mkoutrel "Out1" "landshark_left_wheel_velocity" twist_x])
    "Generator: output relation writes topic 'landshark_left_wheel_velocity', which is not published".
Proof. vm_compute. split; reflexivity. Qed.

(** A published topic used as an input. *)
Example refuse_input_from_published:
  refused (with_inrels landshark
             [mkinrel "landshark_left_wheel_velocity" twist_x "In1";
              mkinrel "landshark_right_wheel_velocity" twist_x "In2";
              mkinrel "landshark_control_base_velocity" twist_x "In3"])
    "Generator: input relation reads topic 'landshark_control_base_velocity', which is not subscribed".
Proof. vm_compute. split; reflexivity. Qed.

(** A relation for an undeclared topic. *)
Example refuse_unknown_topic:
  refused (with_inrels landshark
             [mkinrel "landshark_left_wheel_velocity" twist_x "In1";
              mkinrel "landshark_right_wheel_velocity" twist_x "In2";
              mkinrel "landshark_imu" twist_x "In3"])
    "Generator: input relation for unknown topic 'landshark_imu'".
Proof. vm_compute. split; reflexivity. Qed.

(** A C keyword as a controller input name. *)
Example refuse_keyword:
  refused (with_inrels (with_inputs landshark [("In1", FTprim Pfloat64); ("In2", FTprim Pfloat64); ("int", FTprim Pfloat64)])
             [mkinrel "landshark_left_wheel_velocity" twist_x "In1";
              mkinrel "landshark_right_wheel_velocity" twist_x "In2";
              mkinrel "landshark_gps_velocity" twist_x "int"])
    "Generator: name is not a valid C identifier: 'int'".
Proof. vm_compute. split; reflexivity. Qed.

(** A name reserved by the C standard, and one that is not an identifier. *)
Example refuse_reserved:
  refused (with_inputs landshark [("In1", FTprim Pfloat64); ("In2", FTprim Pfloat64); ("_In3", FTprim Pfloat64)])
    "Generator: name is not a valid C identifier: '_In3'".
Proof. vm_compute. split; reflexivity. Qed.

Example refuse_bad_chars:
  refused (with_topics_msgs landshark
             [left_wheel; right_wheel; gps;
              mktopic "/landshark_control/base_velocity" "base-velocity" "geometry_msgs/TwistStamped" Publish
                      "geometry_msgs_TwistStamped" 1] landshark_msgs)
    "Generator: name is not a valid C identifier: 'ros_advertise_base-velocity'".
Proof. vm_compute. split; reflexivity. Qed.

(** Two topics with the same C name give the same generated names. *)
Example refuse_duplicate_cname:
  refused (with_topics_msgs landshark
             [left_wheel; right_wheel;
              mktopic "/landshark/gps" "landshark_left_wheel_velocity" "geometry_msgs/TwistStamped" Subscribe
                      "geometry_msgs_TwistStamped" 1; base] landshark_msgs)
    "Generator: two topics with the C name 'landshark_left_wheel_velocity'".
Proof. vm_compute. split; reflexivity. Qed.

(** A global that a local would hide. *)
Example refuse_global_hidden_by_local:
  refused {| nm_name := "landshark_controller"; nm_period_ms := 20; nm_ctrl := "Controller";
             nm_in_var := "msg"; nm_in_struct := "ExtU_Controller_T";
             nm_inputs := nm_inputs landshark; nm_out_var := "Controller_Y";
             nm_out_struct := "ExtY_Controller_T"; nm_outputs := nm_outputs landshark;
             nm_msgs := landshark_msgs; nm_topics := nm_topics landshark;
             nm_inrels := nm_inrels landshark; nm_outrels := nm_outrels landshark;
  nm_timeouts := []; nm_fallbacks := []; nm_drels := []; nm_stamps := []; nm_stamp_from := []; nm_strings := [] |}
    "Generator: name defined twice: 'msg'".
Proof. vm_compute. split; reflexivity. Qed.

(** Messages must be defined before they are used. *)
Example refuse_message_order:
  refused (with_topics_msgs landshark (nm_topics landshark)
             [std_msgs_Header; ros_time; geometry_msgs_Vector3; geometry_msgs_Twist;
              geometry_msgs_TwistStamped])
    "Generator: message 'std_msgs_Header' refers to message 'ros_time', which is not defined before it".
Proof. vm_compute. split; reflexivity. Qed.

(** A published field fed twice. *)
Example refuse_published_field_twice:
  refused (with_outrels landshark [mkoutrel "Out1" "landshark_control_base_velocity" twist_x;
                                   mkoutrel "Out1" "landshark_control_base_velocity" twist_x])
    "Generator: published field fed twice: 'landshark_control_base_velocity.twist.linear.x'".
Proof. vm_compute. split; reflexivity. Qed.

(** An output may feed several published fields. *)
Example accept_output_fanout:
  wf (with_outrels landshark [mkoutrel "Out1" "landshark_control_base_velocity" twist_x;
                              mkoutrel "Out1" "landshark_control_base_velocity"
                                       [PField "twist"; PField "angular"; PField "z"]]) = true.
Proof. vm_compute. reflexivity. Qed.

(** Zero queue, non-positive period. *)
Example refuse_queue_0:
  refused (with_topics_msgs landshark
             [left_wheel; right_wheel; gps;
              mktopic "/landshark_control/base_velocity" "landshark_control_base_velocity" "geometry_msgs/TwistStamped" Publish
                      "geometry_msgs_TwistStamped" 0] landshark_msgs)
    "Generator: queue size must be at least 1 for topic '/landshark_control/base_velocity'".
Proof. vm_compute. split; reflexivity. Qed.

Example refuse_period_0:
  refused {| nm_name := "landshark_controller"; nm_period_ms := 0; nm_ctrl := "Controller";
             nm_in_var := "Controller_U"; nm_in_struct := "ExtU_Controller_T";
             nm_inputs := nm_inputs landshark; nm_out_var := "Controller_Y";
             nm_out_struct := "ExtY_Controller_T"; nm_outputs := nm_outputs landshark;
             nm_msgs := landshark_msgs; nm_topics := nm_topics landshark;
             nm_inrels := nm_inrels landshark; nm_outrels := nm_outrels landshark;
  nm_timeouts := []; nm_fallbacks := []; nm_drels := []; nm_stamps := []; nm_stamp_from := []; nm_strings := [] |}
    "Generator: period_ms must be positive".
Proof. vm_compute. split; reflexivity. Qed.

(** A timeout shorter than the period is refused (rule 4.12; the other
    refusals of the rule are in [Freshness.v]). *)
Example refuse_short_timeout:
  refused {| nm_name := nm_name landshark; nm_period_ms := nm_period_ms landshark;
             nm_ctrl := nm_ctrl landshark; nm_in_var := nm_in_var landshark;
             nm_in_struct := nm_in_struct landshark; nm_inputs := nm_inputs landshark;
             nm_out_var := nm_out_var landshark; nm_out_struct := nm_out_struct landshark;
             nm_outputs := nm_outputs landshark; nm_msgs := nm_msgs landshark;
             nm_topics := nm_topics landshark; nm_inrels := nm_inrels landshark;
             nm_outrels := nm_outrels landshark;
             nm_timeouts := [("landshark_gps_velocity", 1%Z)]; nm_fallbacks := []; nm_drels := []; nm_stamps := []; nm_stamp_from := []; nm_strings := [] |}
    "Generator: bad timeout (rule 4.12) on topic 'landshark_gps_velocity': 1 ms must be on a subscribed topic, from the period to 86400000 ms".
Proof. vm_compute. split; reflexivity. Qed.
