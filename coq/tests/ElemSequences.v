(** * Arrays of messages and of strings (issue 15): a run and mutants *)

(** A path follower: it subscribes to [/path], whose message carries
    [poses] as a bounded sequence of at most 3 messages
    ([ros_seq_geometry_msgs_Pose2_3], its [data] an array of
    [geometry_msgs_Pose2] structs), each pose holding a float64 [x] and a
    string [frame] of at most 4 bytes ([ros_string4]): a sequence whose
    elements hold a sequence in turn, as [nav_msgs/Path]'s
    [poses[i].header.frame_id] or [sensor_msgs/JointState]'s [name[i]].
    The controller gets, through ordinary input relations on the leaves
    of the bounded structs, the number of poses and whether there were
    more than 3, pose 1's [x], pose 2's frame length and first byte, and
    byte 3 of pose 0's frame.

    Six paths arrive, of 0, 1, 2, 3, 4 and 6 poses (0, 1, N-1, N, N+1 and
    2N), with junk past every length, the outer one and the frames':
    the interpreter gives the controller, cycle by cycle, what
    [Environment.clamp] says (each of the first [min(len, 3)] poses
    converted, its frame capped at 4 bytes with zeros past its length;
    every other pose zero), so neither junk is ever seen.  Three
    generator mutants are refuted against T2: the pose read one index
    off, the frame's length read from the outer sequence's length, and
    the wrong byte of a frame. *)

From Coq Require Import String List ZArith Lia.
From Flocq Require Import IEEE754.Binary IEEE754.Bits.
From ROSGen Require Import FloatBits Errors Syntax Values Memory Environment Semantics Interp Interpproof
  NodeModel Wellformed Generator Generatorspec DDC Loopproof.
From ROSGenTests Require Import LandShark Mutants Sequences.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope list_scope.

(** ** The model *)

Definition str4 : msgdef :=
  mkmsgdef "ros_string4" [("len", FTprim Puint32); ("truncated", FTprim Pbool);
                          ("data", FTarray (FTprim Puint8) 4)].
Definition pose2 : msgdef :=
  mkmsgdef "geometry_msgs_Pose2" [("x", FTprim Pfloat64); ("frame", FTmsg "ros_string4")].
Definition poses3 : msgdef :=
  mkmsgdef "ros_seq_geometry_msgs_Pose2_3" [("len", FTprim Puint32); ("truncated", FTprim Pbool);
                                           ("data", FTarray (FTmsg "geometry_msgs_Pose2") 3)].
Definition path_msgdef : msgdef :=
  mkmsgdef "nav_msgs_Path" [("poses", FTmsg "ros_seq_geometry_msgs_Pose2_3")].

Definition pathtp : topic := mktopic "/path" "path" "nav_msgs/Path" Subscribe "nav_msgs_Path" 1.

Definition poses (s : string) : path := [PField "poses"; PField s].
Definition pose (i : Z) (p : path) : path := [PField "poses"; PField "data"; PIndex i] ++ p.

Definition follower : node_model := {|
  nm_name := "follower"; nm_period_ms := 20; nm_ctrl := "Controller";
  nm_in_var := "Controller_U"; nm_in_struct := "ExtU_Controller_T";
  nm_inputs := [("NP", FTprim Puint32); ("TP", FTprim Pbool); ("X1", FTprim Pfloat64);
                ("F2L", FTprim Puint32); ("F2B0", FTprim Puint8); ("F0B3", FTprim Puint8)];
  nm_out_var := "Controller_Y"; nm_out_struct := "ExtY_Controller_T";
  nm_outputs := [("Out1", FTprim Pfloat64)];
  nm_msgs := [str4; pose2; poses3; path_msgdef; geometry_msgs_Vector3; geometry_msgs_Twist];
  nm_topics := [pathtp; cmd];
  nm_inrels := [mkinrel "path" (poses "len") "NP"; mkinrel "path" (poses "truncated") "TP";
                mkinrel "path" (pose 1 [PField "x"]) "X1";
                mkinrel "path" (pose 2 [PField "frame"; PField "len"]) "F2L";
                mkinrel "path" (pose 2 [PField "frame"; PField "data"; PIndex 0]) "F2B0";
                mkinrel "path" (pose 0 [PField "frame"; PField "data"; PIndex 3]) "F0B3"];
  nm_outrels := [mkoutrel "Out1" "cmd" [PField "linear"; PField "x"]];
  nm_timeouts := []; nm_fallbacks := []; nm_drels := []; nm_stamps := []; nm_stamp_from := [];
  nm_strings := [] |}.

Example follower_wf: wf follower = true.
Proof. vm_compute. reflexivity. Qed.

Definition follower_result : res program := Eval vm_compute in generate follower.
Definition follower_prog : program :=
  Eval vm_compute in match follower_result with OK p => p | Error _ => mkprogram [] [] "" end.

Lemma follower_generates: generate follower = OK follower_prog.
Proof. vm_compute. reflexivity. Qed.

(** [Main.converted_sequence_elems] applies to [poses]: the path reaches
    the bounded sequence of messages through no other one
    ([bounded_elems_at]); and [Main.converted_sequence] to pose 2's
    frame, which is inside one, does not ([bounded_at] asks for a path
    through no bounded struct): what the callback receives of it follows
    from [clamp] on [poses]. *)
Example poses_bounded:
  bounded_elems_at follower pathtp [PField "poses"] "ros_seq_geometry_msgs_Pose2_3" 3 (Tstruct "geometry_msgs_Pose2").
Proof. repeat split; vm_compute; reflexivity. Qed.

(** ** Paths as they are sent *)

Definition d64 (bits : Z) : float64 := float64_of_bits bits.
Definition x1 : Z := 0x3FF0000000000000.   (**r 1.0 *)
Definition x2 : Z := 0x4000000000000000.   (**r 2.0 *)
Definition x3 : Z := 0x4008000000000000.   (**r 3.0 *)
Definition xj : Z := 0x4022000000000000.   (**r 9.0, past the length *)
Definition bj : Z := 120.                  (**r 'x', past a frame's length *)

(** A pose: its [x] (bits), its frame's length and its four bytes. *)
Definition pose_mv (x : Z) (fl : Z) (bs : list Z) : mval :=
  MVstruct [("x", MVscalar (Vfloat (d64 x)));
            ("frame", MVstruct [("len", MVscalar (Vint fl)); ("truncated", MVscalar (Vint 0));
                                ("data", MVarray (map (fun b => MVscalar (Vint b)) bs))])].

Definition junk_pose : mval := pose_mv xj 4 [bj; bj; bj; bj].

(** A path of [l] poses whose first three are [ps] (the poses past 3 are
    not represented: no node can see them). *)
Definition path_mv (l : Z) (ps : list mval) : mval :=
  MVstruct [("poses", MVstruct [("len", MVscalar (Vint l)); ("truncated", MVscalar (Vint 0));
                                ("data", MVarray ps)])].

Definition paths : list mval :=
  [path_mv 0 [junk_pose; junk_pose; junk_pose];                                        (* 0 poses *)
   path_mv 1 [pose_mv x1 5 [97; 98; 99; 100]; junk_pose; junk_pose];                  (* 1: a frame of 5 bytes *)
   path_mv 2 [pose_mv x1 3 [97; 98; 99; bj]; pose_mv x2 1 [101; bj; bj; bj]; junk_pose]; (* N - 1 *)
   path_mv 3 [pose_mv x1 4 [97; 98; 99; 100]; pose_mv x2 0 [bj; bj; bj; bj];
              pose_mv x3 7 [102; 103; 104; 105]];                                     (* N *)
   path_mv 4 [pose_mv x1 4 [97; 98; 99; 100]; pose_mv x2 0 [bj; bj; bj; bj];
              pose_mv x3 0 [bj; bj; bj; bj]];                                         (* N + 1 *)
   path_mv 6 [pose_mv x1 4 [97; 98; 99; 100]; pose_mv x2 0 [bj; bj; bj; bj];
              pose_mv x3 2 [103; 104; bj; bj]]]%Z.                                    (* 2 N *)

Definition fctx : ros_context unit :=
  mkctx (fun k => match nth_error paths k with
                  | Some mv => [mkarrival "/path" mv 0]
                  | None => []
                  end)
        (fun _ => 0%Z) tt (fun _ _ => (tt, y_out)) Ros1.

Lemma fctx_arrivals_wt: arrivals_wt follower fctx.
Proof.
  intros k a tp H Htp _. apply mval_typecheck_iff.
  simpl in Htp. destruct Htp as [<-|[]].
  simpl in H. do 6 (destruct k as [|k]; [simpl in H; destruct H as [<-|[]]; vm_compute; reflexivity|]).
  simpl in H. destruct k; contradiction.
Qed.

Lemma fctx_controller_wt: controller_wt follower fctx.
Proof. intros s u. apply mval_typecheck_iff. vm_compute. reflexivity. Qed.

(** ** What the controller receives *)

Definition scalar_bits (mv : option mval) : option Z :=
  match mv with
  | Some (MVscalar (Vfloat x)) => Some (bits_of_b64 x)
  | Some (MVscalar (Vint n)) => Some n
  | _ => None
  end.

(** The inputs of each step: [NP], [TP], [X1] (its bits), [F2L], [F2B0], [F0B3]. *)
Definition inputs_of (t : trace) : list (list (option Z)) :=
  flat_map (fun e => match e with
                     | Estep u _ => [map (fun x => scalar_bits (mval_get u [Sfield x]))
                                         ["NP"; "TP"; "X1"; "F2L"; "F2B0"; "F0B3"]]
                     | _ => []
                     end) t.

(** The number of poses capped at 3, truncated for 4 and 6 poses only;
    pose 1's [x] from 2 poses on; pose 2's frame (its length capped at
    4, its first byte) from 3 poses on, 0 when its frame is empty; byte 3
    of pose 0's frame when that frame has 4 bytes or more (5 bytes:
    capped, byte 3 seen; 3 bytes: byte 3 is 0, not the junk). *)
Example follower_run:
  match run_trace 4000 follower_prog fctx 6 with
  | Some t => inputs_of t =
      map (map Some)
      [[0; 0; 0; 0; 0; 0];
       [1; 0; 0; 0; 0; 100];
       [2; 0; x2; 0; 0; 0];
       [3; 0; x2; 4; 102; 100];
       [3; 1; x2; 0; 0; 100];
       [3; 1; x2; 2; 103; 100]]%Z
  | None => False
  end.
Proof. vm_compute. reflexivity. Qed.

(** ** Mutants *)

Definition fcheck : program -> nat -> bool := check_in follower fctx 4000.

Lemma frefute: forall p n, fcheck p n = false -> ~ node_ddc follower p.
Proof. exact (refute_in follower fctx 4000 fctx_arrivals_wt fctx_controller_wt). Qed.

(** The generated program passes (as T2 says it must). *)
Example follower_passes: fcheck follower_prog 6 = true.
Proof. vm_compute. reflexivity. Qed.

(** [h] applied to every field access and index of an expression, inner
    ones first (the pose's index sits under the access to its [x]). *)
Fixpoint deep (h : expr -> expr) (e : expr) : expr :=
  h (match e with
     | Efield a f t => Efield (deep h a) f t
     | Eindex a i t => Eindex (deep h a) i t
     | _ => e
     end).

(** (s1) the pose read one index off: pose 2's [x] for pose 1's (with
    two poses, pose 2 is zero and pose 1's [x] is 2.0) *)
Definition m_pose_off : program := on_function "path_callback" (map_exprs (deep shift_index)) follower_prog.
Theorem m_pose_off_refuted: ~ node_ddc follower m_pose_off.
Proof. apply (frefute _ 3). vm_compute. reflexivity. Qed.

(** (s2) the frame's length read from the outer sequence: [poses.len]
    for [poses.data[2].frame.len] (one pose: 1 instead of 0) *)
Definition outer_len (e : expr) : expr :=
  match e with
  | Efield (Efield (Eindex (Efield b "data" _) _ _) "frame" _) "len" t => Efield b "len" t
  | _ => e
  end.
Definition m_outer_len : program := on_function "path_callback" (map_exprs outer_len) follower_prog.
Theorem m_outer_len_refuted: ~ node_ddc follower m_outer_len.
Proof. apply (frefute _ 2). vm_compute. reflexivity. Qed.

(** (s3) the wrong byte of a frame: byte 0 of pose 0's frame for its
    byte 3 (a frame of 5 bytes, "abcd" kept: 'a' instead of 'd') *)
Definition first_byte (e : expr) : expr :=
  match e with
  | Eindex (Efield (Efield (Eindex s (Econst_int 0 ti) ts) "frame" tf) "data" td) (Econst_int 3 tj) t =>
      Eindex (Efield (Efield (Eindex s (Econst_int 0 ti) ts) "frame" tf) "data" td) (Econst_int 0 tj) t
  | _ => e
  end.
Definition m_first_byte : program := on_function "path_callback" (map_exprs first_byte) follower_prog.
Theorem m_first_byte_refuted: ~ node_ddc follower m_first_byte.
Proof. apply (frefute _ 2). vm_compute. reflexivity. Qed.
