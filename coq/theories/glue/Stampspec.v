(** * Stamps (rule 4.13): what well-formedness says of a stamp *)

(** A stamp's [sec] and [nsec] are leaves of the model's time message
    ([NodeModel.time_msg]): ROS 1's [ros_time], [uint32 sec] and [uint32
    nsec], or ROS 2's [builtin_interfaces_Time], [int32 sec] and [uint32
    nanosec] ([time_sec_prim], [time_nsec_field]), for the stamped topic
    ([wf_stamp]) and for the subscribed topic a stamp is copied from
    ([wf_stamp_from]). *)

From Coq Require Import String List ZArith Bool.
From ROSGen Require Import Errors Syntax Values Maps NodeModel Wellformed Generator Generatorspec.
Import ListNotations.

Local Open Scope string_scope.
Local Open Scope list_scope.

(** The model's time message has the fields [sec] of type
    [time_sec_prim] and [time_nsec_field] of type [uint32]. *)
Lemma time_msg_fields:
  forall msgs id, time_msg_ok msgs = true -> ident_eqb id (time_msg msgs) = true ->
  resolve msgs (FTmsg id) [PField "sec"] = Some (FTprim (time_sec_prim msgs))
  /\ resolve msgs (FTmsg id) [PField (time_nsec_field msgs)] = Some (FTprim Puint32).
Proof.
  intros msgs id TM R. apply ident_eqb_true in R; subst id.
  unfold time_msg_ok in TM.
  destruct (find_msg msgs (time_msg msgs)) as [md|] eqn:Fm; [|discriminate].
  destruct (md_fields md) as [|[s [q1| |] ] [|[n [q2| |]] [|]]] eqn:Fd; try discriminate;
    destruct q2; try discriminate.
  rewrite !andb_true_iff in TM; destruct TM as [[Es Eq] En].
  apply ident_eqb_true in Es, En. apply prim_eqb_true in Eq. subst s n q1.
  simpl. rewrite Fm, Fd. simpl. split; [reflexivity|].
  destruct (string_dec (time_nsec_field msgs) "sec") as [E|_].
  - unfold time_nsec_field in E. destruct (time_is_ros2 msgs); discriminate.
  - destruct (string_dec (time_nsec_field msgs) (time_nsec_field msgs)) as [_|N]; [reflexivity|].
    contradiction N; reflexivity.
Qed.

(** A stamped topic is a published topic whose stamp path leads to a
    field of the model's time message, and no output relation of the
    topic writes inside the stamp. *)
Lemma wf_stamp:
  forall m tp sp, wf_facts m -> In tp (published m) ->
  find_assoc (tp_cname tp) (nm_stamps m) = Some sp ->
     resolve (nm_msgs m) (FTmsg (tp_msg tp)) (sp ++ [PField "sec"]) = Some (FTprim (time_sec_prim (nm_msgs m)))
  /\ resolve (nm_msgs m) (FTmsg (tp_msg tp)) (sp ++ [PField (time_nsec_field (nm_msgs m))]) = Some (FTprim Puint32)
  /\ forall o q, In o (nm_outrels m) -> or_topic o = tp_cname tp -> or_path o <> sp ++ q.
Proof.
  intros m tp sp W Htp F.
  assert (Hin: In (tp_cname tp, sp) (nm_stamps m)) by (apply find_assoc_In; auto).
  generalize (wf_stamps m W _ Hin). unfold stamp_ok; cbn [fst snd].
  assert (Htop: In tp (nm_topics m)) by (unfold published in Htp; apply filter_In in Htp; tauto).
  rewrite tables_topics, (In_find_topic _ tp (wf_cnames_nodup m W) Htop).
  rewrite !andb_true_iff. intros [[_ R] NO].
  destruct (resolve (nm_msgs m) (FTmsg (tp_msg tp)) sp) as [[| id |]|] eqn:Rs; try discriminate.
  assert (TM: time_msg_ok (nm_msgs m) = true) by (apply (wf_time_msg m W); intros E; rewrite E in Hin; contradiction).
  destruct (time_msg_fields _ _ TM R) as [Fs Fn].
  rewrite !resolve_app, Rs. split; [exact Fs|split; [exact Fn|]].
  intros o q Ho Eo Ep. rewrite forallb_forall in NO. generalize (NO o Ho).
  rewrite Eo, ident_eqb_refl, Ep, path_prefixb_app. discriminate.
Qed.

(** A copied stamp comes from a field of the model's time message in a
    subscribed topic's message, for a stamped topic. *)
Lemma wf_stamp_from:
  forall m c s sp', wf_facts m -> In (c, (s, sp')) (nm_stamp_from m) ->
  exists tp,
     find_topic (nm_topics m) s = Some tp /\ is_subscribed tp = true
  /\ resolve (nm_msgs m) (FTmsg (tp_msg tp)) (sp' ++ [PField "sec"]) = Some (FTprim (time_sec_prim (nm_msgs m)))
  /\ resolve (nm_msgs m) (FTmsg (tp_msg tp)) (sp' ++ [PField (time_nsec_field (nm_msgs m))]) = Some (FTprim Puint32)
  /\ exists sp, In (c, sp) (nm_stamps m).
Proof.
  intros m c s sp' W Hin.
  generalize (wf_stamp_froms m W _ Hin). unfold stamp_from_ok; cbn [fst snd].
  rewrite tables_topics. rewrite !andb_true_iff. intros [Ex R].
  apply existsb_exists in Ex. destruct Ex as ([c' sp] & Hst & Ec). apply ident_eqb_true in Ec. simpl in Ec. subst c'.
  destruct (find_topic (nm_topics m) s) as [tp|]; [|discriminate].
  apply andb_true_iff in R. destruct R as [S R].
  destruct (resolve (nm_msgs m) (FTmsg (tp_msg tp)) sp') as [[| id |]|] eqn:Rs; try discriminate.
  assert (TM: time_msg_ok (nm_msgs m) = true) by (apply (wf_time_msg m W); intros E; rewrite E in Hst; contradiction).
  destruct (time_msg_fields _ _ TM R) as [Fs Fn].
  exists tp. rewrite !resolve_app, Rs. repeat split; eauto.
Qed.
