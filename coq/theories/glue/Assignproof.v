(** * Properties of the glue-code generator: the rest of T3 *)

(** The paper's Section 6 properties, after relation consistency
    ([Generatorproof]): valid assignment via type checking
    ([type_checking_input_glue_sound], [type_checking_input_glue_generated],
    Figure 16, and [generate_valid_assignments] for every generated
    function), and preservation ([loop_input_glue_then_step],
    [generate_inputs_written_only_by_input_glue],
    [generate_outputs_not_written], [generate_inputs_address_not_taken]);
    and the facts on the names after the controller's that the proofs of
    T1 and T2 use ([wf_controller_vars_fresh], [clock_name_in_after]). *)

From Coq Require Import String Ascii List ZArith Bool Lia.
From ROSGen Require Import Errors Syntax Values Operators Maps NodeModel Wellformed Generator Generatorspec Stampspec Generatorproof.
Import ListNotations.

Local Open Scope string_scope.
Local Open Scope list_scope.
Local Open Scope error_monad_scope.

(** ** Valid assignment via type checking (the paper's Figure 16) *)

(** The paper's check that the two sides of the copies of [input_glue]
    have equal types. *)
Fixpoint type_checking_input_glue (ltype_global_fields ltype_controller_fields : list type) : bool :=
  match ltype_global_fields, ltype_controller_fields with
  | [], [] => true
  | tg :: ltypeg, tc :: ltypec => type_eqb tg tc && type_checking_input_glue ltypeg ltypec
  | _, _ => false
  end.

Theorem type_checking_input_glue_sound:
  forall l1 l2, type_checking_input_glue l1 l2 = true -> l1 = l2.
Proof.
  induction l1 as [|t1 l1 IH]; intros [|t2 l2]; simpl; try congruence.
  rewrite andb_true_iff, type_eqb_true; intros [-> E]. f_equal; auto.
Qed.

(** The generator emits [input_glue] only for models where the check
    succeeds. *)
Theorem type_checking_input_glue_generated:
  forall m, wf m = true ->
  type_checking_input_glue (map typeof (gen_list_global_expr_input_glue m (nm_inrels m)))
                           (map typeof (gen_list_controller_expr_input_glue m (nm_inrels m))) = true.
Proof.
  intros m Hwf. apply wf_facts_intro in Hwf.
  unfold gen_list_global_expr_input_glue, gen_list_controller_expr_input_glue.
  generalize (input_copy_typed m Hwf). induction (nm_inrels m) as [|ir l IH]; simpl; intros T; auto.
  rewrite andb_true_iff, type_eqb_true; split.
  - destruct (T ir) as (T1 & _ & T2 & _); simpl; auto; congruence.
  - apply IH; intros; apply T; auto.
Qed.

(** The same check on each published topic's copies. *)
Definition type_checking_output_glue := type_checking_input_glue.

Theorem type_checking_output_glue_generated:
  forall m tp, wf m = true -> In tp (nm_topics m) ->
  type_checking_output_glue
    (map typeof (gen_list_controller_expr_output_glue m (topic_outrels (make_tables m) (tp_cname tp))))
    (map typeof (gen_list_message_expr_output_glue m (tp_msg tp) (topic_outrels (make_tables m) (tp_cname tp))))
  = true.
Proof.
  intros m tp Hwf Htp. apply wf_facts_intro in Hwf.
  unfold gen_list_controller_expr_output_glue, gen_list_message_expr_output_glue.
  generalize (output_copy_typed m Hwf tp). generalize (topic_outrels (make_tables m) (tp_cname tp)).
  induction l as [|o l IH]; simpl; intros T; auto.
  rewrite andb_true_iff, type_eqb_true; split.
  - destruct (T o) as (T1 & _ & T2 & _); simpl; auto; congruence.
  - apply IH; intros; apply T; auto.
Qed.

(** Valid assignments in a function body, with its temporaries [temps]:
    both sides of [lhs = rhs] have the same scalar type and are well-typed
    accesses, a temporary is read at its declared type, [tmp = e] and
    [tmp = f(...)] store into a temporary of the value's type. *)
Definition is_scalar (t : type) : bool :=
  match t with Tint _ _ | Tlong _ | Tfloat _ => true | _ => false end.

(** A right-hand side: a temporary read at its type, a constant, an
    arithmetic operation on two operands of one type, allowed by
    [binop_type], a cast between scalar types, or a well-typed place. *)
Fixpoint wt_rhs (ce : list composite_definition) (temps : list (ident * type)) (e : expr) : Prop :=
  match e with
  | Etempvar x t => find_assoc x temps = Some t
  | Econst_int _ _ | Econst_long _ _ | Econst_float _ _ | Econst_single _ _ => True
  | Ebinop op a1 a2 t =>
      typeof a1 = typeof a2 /\ binop_type op (typeof a1) = Some t
      /\ wt_rhs ce temps a1 /\ wt_rhs ce temps a2
  | Ecast a t => is_scalar (typeof a) = true /\ is_scalar t = true /\ wt_rhs ce temps a
  | _ => wt_place ce e
  end.

Fixpoint valid_assignments (ce : list composite_definition) (temps : list (ident * type))
                           (s : statement) : Prop :=
  match s with
  | Sassign l r =>
      typeof l = typeof r /\ is_scalar (typeof l) = true /\ wt_place ce l /\ wt_rhs ce temps r
  | Sset x e => find_assoc x temps = Some (typeof e) /\ (wt_place ce e \/ wt_rhs ce temps e)
  | Scall (Some x) f _ =>
      match typeof f with Tfunction _ r => find_assoc x temps = Some r | _ => False end
  | Ssequence s1 s2 | Sifthenelse _ s1 s2 =>
      valid_assignments ce temps s1 /\ valid_assignments ce temps s2
  | Sloop s1 => valid_assignments ce temps s1
  | _ => True
  end.

Lemma valid_assignments_seq:
  forall ce temps l, (forall s, In s l -> valid_assignments ce temps s) ->
  valid_assignments ce temps (seq_of l).
Proof. induction l as [|s l IH]; simpl; intros H; auto. Qed.

Lemma ctype_of_prim_scalar: forall q, is_scalar (ctype_of_prim q) = true.
Proof. destruct q; reflexivity. Qed.

Lemma typeof_zero_of: forall q, typeof (zero_of q) = ctype_of_prim q.
Proof. destruct q; reflexivity. Qed.

Lemma valid_copy:
  forall ce temps q d s,
  find_assoc (temp_name q) temps = Some (ctype_of_prim q) ->
  typeof d = ctype_of_prim q -> wt_place ce d ->
  typeof s = ctype_of_prim q -> wt_place ce s ->
  valid_assignments ce temps (copy q d s).
Proof.
  intros; simpl. rewrite H2, H0. repeat split; auto. apply ctype_of_prim_scalar.
Qed.

(** The stores of the constant strings are valid assignments. *)
Lemma valid_strings:
  forall m tp temps, wf_facts m -> In tp (published m) ->
  valid_assignments (composites m) temps (strings_stmts m (tp_cname tp) (tp_msg tp)).
Proof.
  intros m tp temps W Htp. unfold strings_stmts.
  apply valid_assignments_seq. intros st Hst.
  apply in_map_iff in Hst; destruct Hst as (a & <- & Ha).
  apply in_flat_map in Ha. destruct Ha as ([sp bs] & Hsb & Ha).
  apply In_topic_strings in Hsb.
  destruct (string_store_leaf m tp sp bs a W Htp Hsb Ha) as [R _].
  destruct (leaf_path_expr_typed m _ _ _ (deref_param command_param (tp_msg tp)) R)
    as [T1 W1]; auto; [constructor|].
  unfold const_store. simpl. rewrite T1. repeat split; auto. apply ctype_of_prim_scalar.
Qed.

Lemma typeof_const_of: forall q v, typeof (const_of q v) = ctype_of_prim q.
Proof. intros q v; destruct v; simpl; auto; apply typeof_zero_of. Qed.

Lemma wt_rhs_const_of: forall ce temps q v, wt_rhs ce temps (const_of q v).
Proof. intros ce temps q v; destruct v; simpl; auto; destruct q; exact I. Qed.

Lemma valid_copies:
  forall ce temps qs ld ls,
  (forall i q d s, nth_error qs i = Some q -> nth_error ld i = Some d -> nth_error ls i = Some s ->
     find_assoc (temp_name q) temps = Some (ctype_of_prim q)
     /\ typeof d = ctype_of_prim q /\ wt_place ce d
     /\ typeof s = ctype_of_prim q /\ wt_place ce s) ->
  valid_assignments ce temps (seq_of (copies qs ld ls)).
Proof.
  induction qs as [|q qs IH]; intros [|d ld] [|s ls] H; simpl; auto. split.
  - destruct (H O q d s) as (? & ? & ? & ? & ?); auto. apply valid_copy; auto.
  - apply IH. intros i; apply (H (S i)).
Qed.

Lemma nth_error_map3:
  forall (A : Type) (fq : A -> prim) (fd fs : A -> expr) l i q d s,
  nth_error (map fq l) i = Some q -> nth_error (map fd l) i = Some d -> nth_error (map fs l) i = Some s ->
  exists a, In a l /\ q = fq a /\ d = fd a /\ s = fs a.
Proof.
  intros A fq fd fs l i q d s E1 E2 E3.
  rewrite nth_error_map in E1, E2, E3.
  destruct (nth_error l i) as [a|] eqn:E; simpl in *; try discriminate.
  inversion E1; inversion E2; inversion E3; subst. exists a; split; auto.
  eapply nth_error_In; eauto.
Qed.

Lemma ros_externals_not_internal: forall m id f, ~ In (id, Gfun (Internal f)) (ros_externals m).
Proof.
  intros m id f H. unfold ros_externals, time_externals, now_externals, stamp_externals in H.
  destruct (timed m), (nm_stamps m); simpl in H; intuition discriminate.
Qed.

Lemma clock_globals_not_internal: forall m id f, ~ In (id, Gfun (Internal f)) (flat_map clock_globals (timed m)).
Proof.
  intros m id f H. apply in_flat_map in H. destruct H as (tp & _ & H). simpl in H; intuition discriminate.
Qed.

(** The freshness statements of [input_glue] (rule 4.12) are valid
    assignments. *)
Lemma reads_age_fallback:
  forall m ir, In ir (nm_inrels m) -> has_fallback m ir = true -> reads_age m = true.
Proof.
  intros m ir Hir H. unfold reads_age. apply orb_true_intro; left. apply existsb_exists; eauto.
Qed.

Lemma reads_age_derived:
  forall m dr, In dr (nm_drels m) -> dr_kind dr = Dage_ms -> reads_age m = true.
Proof.
  intros m dr Hdr K. unfold reads_age. apply orb_true_intro; right. apply existsb_exists.
  exists dr; split; auto. unfold is_age; rewrite K; auto.
Qed.

Lemma reads_flag_derived:
  forall m dr, In dr (nm_drels m) -> dr_kind dr <> Dage_ms -> reads_flag m = true.
Proof.
  intros m dr Hdr K. unfold reads_flag. apply existsb_exists.
  exists dr; split; auto. unfold is_age; destruct (dr_kind dr); auto; congruence.
Qed.

Lemma valid_timed:
  forall m temps, wf_facts m ->
  (reads_age m = true -> find_assoc now_temp temps = Some (Tlong Unsigned)) ->
  (reads_age m = true -> find_assoc age_temp temps = Some (Tlong Unsigned)) ->
  (reads_flag m = true -> find_assoc (temp_name Pbool) temps = Some (ctype_of_prim Pbool)) ->
  valid_assignments (composites m) temps (timed_stmts m (make_tables m)).
Proof.
  intros m temps W TN TA TB. unfold timed_stmts. apply valid_assignments_seq.
  assert (AGE: reads_age m = true -> forall c, valid_assignments (composites m) temps (age_stmt c)).
  { intros R c. specialize (TN R). specialize (TA R).
    simpl; repeat split; auto; right; simpl; repeat split; auto; constructor. }
  intros st Hst. apply in_app_iff in Hst. destruct Hst as [Hst|Hst].
  { destruct (reads_age m) eqn:R; [|contradiction]. destruct Hst as [<-|[]]. simpl; auto. }
  apply in_app_iff in Hst. destruct Hst as [Hst|Hst]; [|apply in_app_iff in Hst; destruct Hst as [Hst|Hst]].
  - apply in_map_iff in Hst. destruct Hst as (ir & <- & Hir).
    apply filter_In in Hir. destruct Hir as [Hir HF].
    specialize (AGE (reads_age_fallback m ir Hir HF)).
    destruct (input_copy_typed m W ir Hir) as (_ & _ & T2 & W2).
    unfold fallback_stmt. destruct (find_assoc (ir_input ir) (nm_fallbacks m)); [|exact I].
    destruct (timeout_of m (ir_topic ir)); [|exact I].
    split; [apply AGE|].
    simpl. rewrite typeof_const_of, T2.
    repeat split; auto using ctype_of_prim_scalar, wt_rhs_const_of.
  - apply in_map_iff in Hst. destruct Hst as (dr & <- & Hdr).
    destruct (wf_drel m dr W Hdr) as (tp' & _ & _ & I).
    assert (Hp: input_prim (make_tables m) (dr_input dr) [] = derived_prim (dr_kind dr))
      by (eapply input_prim_tables; eauto; reflexivity).
    assert (WD: wt_place (composites m) (derived_dst m (make_tables m) dr)).
    { unfold derived_dst, in_var_expr. econstructor; [constructor|reflexivity|].
      rewrite Hp. apply (field_type_inputs m W _ _ I). }
    unfold derived_stmt. destruct (dr_kind dr) eqn:K.
    + assert (TB' := TB (reads_flag_derived m dr Hdr ltac:(congruence))).
      apply valid_copy; auto; try constructor.
      unfold derived_dst. simpl. rewrite Hp. auto.
    + assert (TB' := TB (reads_flag_derived m dr Hdr ltac:(congruence))).
      apply valid_copy; auto; try constructor.
      unfold derived_dst. simpl. rewrite Hp. auto.
    + assert (TA' := TA (reads_age_derived m dr Hdr K)).
      split; [apply (AGE (reads_age_derived m dr Hdr K))|].
      unfold derived_dst in *. simpl. rewrite Hp. simpl. rewrite Hp in WD. repeat split; auto.
  - apply in_map_iff in Hst. destruct Hst as (tp & <- & _). simpl. repeat split; auto. constructor.
Qed.

(** The clock update of a callback is valid assignments. *)
Lemma valid_clock:
  forall ce temps c, find_assoc (temp_name Puint64) temps = Some (Tlong Unsigned) ->
  valid_assignments ce temps (clock_stmts c).
Proof. intros; simpl; repeat split; auto; constructor. Qed.

Lemma output_temps:
  forall m tp o, In o (topic_outrels (make_tables m) (tp_cname tp)) ->
  find_assoc (temp_name (outrel_prim (make_tables m) o))
             (fn_temps (output_glue_function m (make_tables m) tp))
  = Some (ctype_of_prim (outrel_prim (make_tables m) o)).
Proof.
  intros m tp o Ho. unfold output_glue_function.
  destruct (topic_stamp m (tp_cname tp)); apply temps_of_find; [apply in_or_app; right|]; apply in_map_iff; eauto.
Qed.

Lemma output_temp_uint:
  forall m tp sp, topic_stamp m (tp_cname tp) = Some sp ->
  find_assoc (temp_name Puint32) (fn_temps (output_glue_function m (make_tables m) tp))
  = Some (ctype_of_prim Puint32).
Proof.
  intros m tp sp E. unfold output_glue_function. rewrite E. apply temps_of_find; left; auto.
Qed.

Lemma output_temp_sec:
  forall m tp sp sf, topic_stamp m (tp_cname tp) = Some sp -> topic_stamp_from m (tp_cname tp) = Some sf ->
  find_assoc (temp_name (time_sec_prim (nm_msgs m))) (fn_temps (output_glue_function m (make_tables m) tp))
  = Some (ctype_of_prim (time_sec_prim (nm_msgs m))).
Proof.
  intros m tp sp sf E F. unfold output_glue_function. rewrite E. apply temps_of_find.
  unfold stamp_prims. rewrite F. right; left; auto.
Qed.

(** The stamp's seconds, converted to ROS 2's [int32]: of the type of
    the field [sec]. *)
Lemma typeof_stamp_sec_expr:
  forall m, typeof (stamp_sec_expr m) = ctype_of_prim (time_sec_prim (nm_msgs m)).
Proof. intros m. unfold stamp_sec_expr, time_sec_prim. destruct (time_is_ros2 (nm_msgs m)); reflexivity. Qed.

(** The stamp statements of a stamped topic are valid assignments. *)
Lemma valid_stamp:
  forall m tp sp temps, wf_facts m -> In tp (published m) -> topic_stamp m (tp_cname tp) = Some sp ->
  find_assoc (temp_name Puint32) temps = Some (ctype_of_prim Puint32) ->
  (forall sf, topic_stamp_from m (tp_cname tp) = Some sf ->
     find_assoc (temp_name (time_sec_prim (nm_msgs m))) temps = Some (ctype_of_prim (time_sec_prim (nm_msgs m)))) ->
  valid_assignments (composites m) temps (stamp_stmts m (make_tables m) (tp_cname tp) (tp_msg tp) sp).
Proof.
  intros m tp sp temps W Htp ST TU TS.
  destruct (wf_stamp m tp sp W Htp ST) as (Rs & Rn & _).
  destruct (leaf_path_expr_typed m _ _ _ (deref_param command_param (tp_msg tp)) Rs)
    as [T1 W1]; auto; [constructor|].
  destruct (leaf_path_expr_typed m _ _ _ (deref_param command_param (tp_msg tp)) Rn)
    as [T2 W2]; auto; [constructor|].
  unfold stamp_stmts. destruct (topic_stamp_from m (tp_cname tp)) as [[s0 sp']|] eqn:SF.
  - assert (Hin: In (tp_cname tp, (s0, sp')) (nm_stamp_from m)) by (apply find_assoc_In; auto).
    specialize (TS _ eq_refl).
    destruct (wf_stamp_from m _ _ _ W Hin) as (tp' & Ft & _ & Rs' & Rn' & _).
    rewrite (topic_msg_tables m _ _ Ft).
    destruct (leaf_path_expr_typed m _ _ _ (Evar (msg_var s0) (Tstruct (tp_msg tp'))) Rs')
      as [T3 W3]; auto; [constructor|].
    destruct (leaf_path_expr_typed m _ _ _ (Evar (msg_var s0) (Tstruct (tp_msg tp'))) Rn')
      as [T4 W4]; auto; [constructor|].
    unfold seq_of; cbn [fold_right valid_assignments].
    split; [|split; [|exact I]]; apply valid_copy; auto.
  - simpl. rewrite T1, T2, typeof_stamp_sec_expr. repeat split; auto.
    + apply ctype_of_prim_scalar.
    + unfold stamp_sec_expr. destruct (time_is_ros2 (nm_msgs m)); simpl; auto.
Qed.

(** Every function of the generated program makes only valid assignments. *)
Theorem generate_valid_assignments:
  forall m p id f, generate m = OK p -> find_def p id = Some (Gfun (Internal f)) ->
  valid_assignments (prog_types p) (fn_temps f) (fn_body f).
Proof.
  intros m p id f H F.
  assert (W: wf_facts m) by (apply wf_facts_intro, (generate_sound m p H)).
  rewrite (generate_types m p H).
  apply find_def_build with (m := m) in F; auto.
  unfold build_defs in F; rewrite !in_app_iff in F.
  destruct F as [F|[F|[F|[F|[F|[F|[F|[F|F]]]]]]]].
  - exfalso; eapply ros_externals_not_internal; eauto.
  - apply in_flat_map in F; destruct F as (tp & _ & F).
    unfold topic_externals in F; destruct (tp_dir tp); simpl in F; intuition discriminate.
  - simpl in F; intuition discriminate.
  - apply in_map_iff in F; destruct F as (tp & E & _); discriminate.
  - exfalso; eapply clock_globals_not_internal; eauto.
  - (* callbacks *)
    apply in_map_iff in F; destruct F as (tp & E & Htp); inversion E; subst f; clear E.
    assert (BASE: forall temps, (forall l, In l (read_leaves m tp) ->
                       find_assoc (temp_name (snd l)) temps = Some (ctype_of_prim (snd l))) ->
              valid_assignments (composites m) temps
              (seq_of (map (leaf_copy (composites m) (Evar (msg_var (tp_cname tp)) (Tstruct (tp_msg tp)))
                                      (deref_param msg_param (tp_msg tp))) (read_leaves m tp)))).
    { intros temps Ht. apply valid_assignments_seq. intros st Hst.
      apply in_map_iff in Hst; destruct Hst as ([pa q] & <- & Hl).
      assert (Hl' := Hl). apply filter_In in Hl' as [Hl' _].
      apply leaves_spec in Hl' as R; auto.
      destruct (leaf_path_expr_typed m _ _ _ (Evar (msg_var (tp_cname tp)) (Tstruct (tp_msg tp))) R)
        as [T1 W1]; auto; [constructor|].
      destruct (leaf_path_expr_typed m _ _ _ (deref_param msg_param (tp_msg tp)) R)
        as [T2 W2]; auto; [constructor|].
      apply valid_copy; auto; apply (Ht (pa, q) Hl). }
    unfold callback_function. destruct (is_timed m (tp_cname tp));
      [|destruct (direct_of m (tp_cname tp)) as [|ir0 ds] eqn:D]; cbn [fn_body fn_temps].
    + split; [apply BASE|apply valid_clock].
      * intros l Hl. apply temps_of_find. right; apply in_map; auto.
      * apply (temps_of_find Puint64). left; auto.
    + apply BASE. intros l Hl. apply temps_of_find. apply in_map; auto.
    + split.
      * apply BASE. intros l Hl. apply temps_of_find. apply in_or_app; left; apply in_map; auto.
      * apply valid_assignments_seq. intros st Hst. rewrite <- D in Hst.
        apply in_map_iff in Hst; destruct Hst as (ir & <- & Hir).
        assert (Hir' := Hir). apply direct_of_In in Hir' as (Hin & _ & _).
        destruct (input_copy_typed m W ir Hin) as (_ & _ & T3 & W3).
        destruct (direct_src_typed m W tp ir) as (T4 & W4); auto.
        { apply in_subscribed in Htp; tauto. }
        apply valid_copy; auto. apply temps_of_find. apply in_or_app; right. rewrite <- D. apply in_map; auto.
  - (* input_glue *)
    simpl in F; destruct F as [E|[]]; inversion E; subst f; clear E.
    destruct (generate_input_glue m p H) as (f & Ff & _ & _ & _ & Fb & _ & Ft & Fn).
    assert (Ef: f = input_glue_function m (make_tables m)).
    { rewrite (generate_find_def m p input_glue_name (Gfun (Internal (input_glue_function m (make_tables m)))) H) in Ff;
        [congruence|].
      unfold build_defs; rewrite !in_app_iff. do 6 right; left. simpl; auto. }
    subst f. rewrite input_glue_body.
    assert (BASE: valid_assignments (composites m) (fn_temps (input_glue_function m (make_tables m))) (input_base m)).
    { unfold input_base. apply valid_copies. intros i q d s E1 E2 E3.
      destruct (nth_error_map3 _ _ _ _ _ _ _ _ _ E1 E2 E3) as (ir & Hir & -> & -> & ->).
      destruct (input_copy_typed m W ir (incl_glue_inrels m ir Hir)) as (? & ? & ? & ?).
      repeat split; auto. }
    destruct (timed m) eqn:T; auto. split; auto.
    destruct (Fn ltac:(congruence)) as (N12 & N3). apply valid_timed; auto; intros R; apply N12; auto.
  - (* output_glue *)
    apply in_map_iff in F; destruct F as (tp & E & Htp); inversion E; subst f; clear E.
    assert (Hpub := Htp).
    apply in_published in Htp; destruct Htp as [Htp _].
    assert (BASE: valid_assignments (composites m) (fn_temps (output_glue_function m (make_tables m) tp))
                    (output_base m tp)).
    2:{ rewrite output_glue_body. split; [|apply valid_strings; auto].
        unfold output_pre. destruct (topic_stamp m (tp_cname tp)) as [sp|] eqn:ST; auto.
        split; auto. apply valid_stamp; auto; [eapply output_temp_uint; eauto|].
        intros sf F. eapply output_temp_sec; eauto. }
    unfold output_base. split.
    + apply valid_assignments_seq. intros st Hst.
      apply in_map_iff in Hst; destruct Hst as ([pa q] & <- & Hl).
      apply leaves_spec in Hl as R; auto.
      destruct (leaf_path_expr_typed m _ _ _ (deref_param command_param (tp_msg tp)) R)
        as [T1 W1]; auto; [constructor|].
      simpl. rewrite T1, typeof_zero_of. repeat split; auto.
      apply ctype_of_prim_scalar. destruct q; exact I.
    + apply valid_copies. intros i q d s E1 E2 E3.
      destruct (nth_error_map3 _ _ _ _ _ _ _ _ _ E1 E2 E3) as (o & Ho & -> & -> & ->).
      destruct (output_copy_typed m W tp o Htp Ho) as (? & ? & ? & ?).
      repeat split; auto. apply output_temps; auto.
  - (* loop and main *)
    simpl in F; destruct F as [E|[E|[]]]; inversion E; subst f; clear E.
    + simpl. repeat split; auto.
      apply valid_assignments_seq. intros st Hst. apply in_app_iff in Hst.
      destruct Hst as [Hst|[<-|[]]]; simpl; auto.
      apply in_flat_map in Hst; destruct Hst as (tp & _ & Hst).
      simpl in Hst; destruct Hst as [<-|[<-|[]]]; simpl; auto.
    + unfold main_function; cbn [fn_body fn_temps].
      apply valid_assignments_seq. intros st Hst. unfold main_stmts in Hst. rewrite !in_app_iff in Hst.
      destruct Hst as [Hst|[Hst|[Hst|Hst]]].
      * simpl in Hst; destruct Hst as [<-|[<-|[]]]; simpl; auto.
      * apply in_map_iff in Hst; destruct Hst as (tp & <- & _); simpl; auto.
      * apply in_map_iff in Hst; destruct Hst as (tp & <- & _); simpl; auto.
      * simpl in Hst; destruct Hst as [<-|[<-|[]]]; simpl; auto.
Qed.

(** ** Preservation *)

(** In each cycle of [loop], nothing runs between the call to [input_glue]
    and the call to the controller's step function: the statement after
    [input_glue();] is [Controller_step();]. *)
Theorem loop_input_glue_then_step:
  forall m p, generate m = OK p ->
  exists f rest,
     find_def p loop_name = Some (Gfun (Internal f))
  /\ fn_body f = Sloop (seq_of ([Scall (Some ok_temp) (Evar ros_ok_name (Tfunction [] tint)) [];
                                 Sifthenelse (Etempvar ok_temp tint) Sskip Sbreak;
                                 call0 ros_spinOnce_name]
                                ++ call0 input_glue_name :: call0 (step_name m) :: rest)).
Proof.
  intros m p H. destruct (generate_loop m p H) as (f & F & _ & _ & _ & _ & _ & B).
  exists f, (flat_map publish_stmts (published m) ++ [call0 ros_rate_sleep_name]).
  split; auto.
Qed.

(** The places assigned by a statement ([lhs] of every [lhs = rhs]). *)
Fixpoint assigned_places (s : statement) : list (option (place_root * path)) :=
  match s with
  | Sassign l _ => [expr_place l]
  | Ssequence s1 s2 | Sifthenelse _ s1 s2 => assigned_places s1 ++ assigned_places s2
  | Sloop s1 => assigned_places s1
  | _ => []
  end.

Lemma assigned_places_seq:
  forall l, assigned_places (seq_of l) = flat_map assigned_places l.
Proof. induction l as [|s l IH]; simpl; auto. rewrite IH; auto. Qed.

Lemma assigned_places_copies:
  forall qs ld ls pl, In pl (assigned_places (seq_of (copies qs ld ls))) ->
  exists d, In d ld /\ pl = expr_place d.
Proof.
  induction qs as [|q qs IH]; intros [|d ld] [|s ls] pl; simpl; try tauto.
  intros [<-|H]; [exists d; auto|]. destruct (IH _ _ _ H) as (d' & ? & ?). exists d'; auto.
Qed.

(** Which generated function assigns what: a callback assigns only its
    topic's global message, and, if the topic is timed, its clock, else
    the leaves of [Controller_U] of its direct input relations (rule
    4.16);
    [input_glue] only fields of [Controller_U] and the [c_new] flags of
    the timed topics; [output_glue_c] only through its pointer parameter
    [command]; [loop] and [main] assign nothing. *)
Theorem generate_assigned_places:
  forall m p id f, generate m = OK p -> find_def p id = Some (Gfun (Internal f)) ->
  forall pl, In pl (assigned_places (fn_body f)) ->
     (exists tp path, In tp (subscribed m) /\ id = callback_name (tp_cname tp)
                      /\ pl = Some (Rvar (msg_var (tp_cname tp)), path))
  \/ (exists tp x, In tp (timed m) /\ id = callback_name (tp_cname tp)
                   /\ In x (clock_names tp) /\ pl = Some (Rvar x, []))
  \/ (exists tp ir, In tp (subscribed m) /\ id = callback_name (tp_cname tp) /\ In ir (direct_of m (tp_cname tp))
                    /\ pl = Some (Rvar (nm_in_var m), PField (ir_input ir) :: ir_elem ir))
  \/ (exists x path, id = input_glue_name /\ pl = Some (Rvar (nm_in_var m), PField x :: path))
  \/ (exists tp, In tp (timed m) /\ id = input_glue_name /\ pl = Some (Rvar (new_var (tp_cname tp)), []))
  \/ (exists tp path, In tp (published m) /\ id = output_glue_name (tp_cname tp)
                      /\ pl = Some (Rderef command_param, path)).
Proof.
  intros m p id f H F pl Hpl.
  apply find_def_build with (m := m) in F; auto.
  unfold build_defs in F; rewrite !in_app_iff in F.
  destruct F as [F|[F|[F|[F|[F|[F|[F|[F|F]]]]]]]].
  - exfalso; eapply ros_externals_not_internal; eauto.
  - apply in_flat_map in F; destruct F as (tp & _ & F).
    unfold topic_externals in F; destruct (tp_dir tp); simpl in F; intuition discriminate.
  - simpl in F; intuition discriminate.
  - apply in_map_iff in F; destruct F as (tp & E & _); discriminate.
  - exfalso; eapply clock_globals_not_internal; eauto.
  - apply in_map_iff in F; destruct F as (tp & E & Htp); inversion E; subst; clear E.
    assert (BASE: In pl (assigned_places (seq_of (map (leaf_copy (composites m) (Evar (msg_var (tp_cname tp)) (Tstruct (tp_msg tp)))
                                      (deref_param msg_param (tp_msg tp))) (read_leaves m tp)))) ->
                  exists path, pl = Some (Rvar (msg_var (tp_cname tp)), path)).
    { clear Hpl. intros Hpl. rewrite assigned_places_seq in Hpl.
      apply in_flat_map in Hpl; destruct Hpl as (st & Hst & Hpl).
      apply in_map_iff in Hst; destruct Hst as ([pa q] & <- & _).
      simpl in Hpl; destruct Hpl as [<-|[]].
      exists pa. apply expr_place_path_expr with (q := []); auto. }
    unfold callback_function in Hpl. destruct (is_timed m (tp_cname tp)) eqn:T; cbn [fn_body] in Hpl.
    + cbn [assigned_places] in Hpl. apply in_app_iff in Hpl. destruct Hpl as [Hpl|Hpl].
      * left. destruct (BASE Hpl) as (pa & ->). exists tp, pa; auto.
      * right; left. assert (Ht: In tp (timed m)) by (apply filter_In; auto).
        simpl in Hpl. unfold clock_names.
        destruct Hpl as [<-|[<-|[<-|[]]]]; eexists tp, _; repeat split; simpl; eauto.
    + destruct (direct_of m (tp_cname tp)) as [|ir0 ds] eqn:D; cbn [fn_body] in Hpl.
      * left. destruct (BASE Hpl) as (pa & ->). exists tp, pa; auto.
      * cbn [assigned_places] in Hpl. apply in_app_iff in Hpl. destruct Hpl as [Hpl|Hpl].
        -- left. destruct (BASE Hpl) as (pa & ->). exists tp, pa; auto.
        -- right; right; left. rewrite assigned_places_seq in Hpl.
           apply in_flat_map in Hpl; destruct Hpl as (st & Hst & Hpl).
           rewrite <- D in Hst. apply in_map_iff in Hst; destruct Hst as (ir & <- & Hir).
           simpl in Hpl; destruct Hpl as [<-|[]].
           exists tp, ir; repeat split; auto.
           unfold input_dst. apply expr_place_path_expr with (q := []); auto.
  - simpl in F; destruct F as [E|[]]; inversion E; subst; clear E.
    rewrite input_glue_body in Hpl.
    assert (BASE: In pl (assigned_places (input_base m)) -> exists x path, pl = Some (Rvar (nm_in_var m), PField x :: path)).
    { clear Hpl. intros Hpl. apply assigned_places_copies in Hpl.
      destruct Hpl as (d & Hd & ->). unfold gen_list_controller_expr_input_glue in Hd.
      apply in_map_iff in Hd; destruct Hd as (ir & <- & _). exists (ir_input ir), (ir_elem ir).
      apply expr_place_path_expr with (q := []); auto. }
    destruct (timed m) as [|tp0 l] eqn:T.
    + right; right; right; left. destruct (BASE Hpl) as (x & pa & ->). eauto.
    + rewrite <- T. cbn [assigned_places] in Hpl. apply in_app_iff in Hpl. destruct Hpl as [Hpl|Hpl].
      * right; right; right; left. destruct (BASE Hpl) as (x & pa & ->). eauto.
      * unfold timed_stmts in Hpl. rewrite T, assigned_places_seq in Hpl.
        apply in_flat_map in Hpl. destruct Hpl as (st & Hst & Hpl).
        rewrite <- T in Hst. apply in_app_iff in Hst. destruct Hst as [Hst|Hst].
        { destruct (reads_age m); [destruct Hst as [<-|[]]; simpl in Hpl; tauto|contradiction]. }
        apply in_app_iff in Hst. destruct Hst as [Hst|Hst]; [|apply in_app_iff in Hst; destruct Hst as [Hst|Hst]].
        -- right; right; right; left. apply in_map_iff in Hst. destruct Hst as (ir & <- & _).
           unfold fallback_stmt in Hpl.
           destruct (find_assoc (ir_input ir) (nm_fallbacks m)); [|simpl in Hpl; tauto].
           destruct (timeout_of m (ir_topic ir)); simpl in Hpl; [|tauto].
           destruct Hpl as [Hpl|[]]. subst pl. exists (ir_input ir), (ir_elem ir).
           split; auto. unfold input_dst. apply expr_place_path_expr with (q := []); auto.
        -- right; right; right; left. apply in_map_iff in Hst. destruct Hst as (dr & <- & _).
           unfold derived_stmt in Hpl.
           unfold derived_dst, in_var_expr in Hpl. destruct (dr_kind dr); simpl in Hpl;
             repeat (destruct Hpl as [Hpl|Hpl]; [subst pl; eauto|]); contradiction.
        -- right; right; right; right; left. apply in_map_iff in Hst. destruct Hst as (tp & <- & Htp).
           simpl in Hpl. destruct Hpl as [<-|[]]. eauto.
  - apply in_map_iff in F; destruct F as (tp & E & Htp); inversion E; subst; clear E.
    right; right; right; right; right. rewrite output_glue_body in Hpl.
    assert (BASE: forall pl, In pl (assigned_places (output_base m tp)) ->
                  exists path, pl = Some (Rderef command_param, path)).
    { clear Hpl. intros pl0 Hpl. unfold output_base in Hpl. simpl in Hpl. apply in_app_iff in Hpl.
      destruct Hpl as [Hpl|Hpl].
      + rewrite assigned_places_seq in Hpl. apply in_flat_map in Hpl.
        destruct Hpl as (st & Hst & Hpl).
        apply in_map_iff in Hst; destruct Hst as ([pa q] & <- & _).
        simpl in Hpl; destruct Hpl as [<-|[]].
        exists pa. apply expr_place_path_expr with (q := []); auto.
      + apply assigned_places_copies in Hpl. destruct Hpl as (d & Hd & ->).
        unfold gen_list_message_expr_output_glue in Hd.
        apply in_map_iff in Hd; destruct Hd as (o & <- & _).
        exists (or_path o). apply expr_place_path_expr with (q := []); auto. }
    cbn [assigned_places] in Hpl. apply in_app_iff in Hpl. destruct Hpl as [Hpl|Hpl].
    2:{ unfold strings_stmts in Hpl. rewrite assigned_places_seq in Hpl. apply in_flat_map in Hpl.
        destruct Hpl as (st & Hst & Hpl). apply in_map_iff in Hst; destruct Hst as (a & <- & _).
        unfold const_store in Hpl. simpl in Hpl; destruct Hpl as [<-|[]].
        eexists tp, _; repeat split; auto. apply expr_place_path_expr with (q := []); auto. }
    unfold output_pre in Hpl.
    destruct (topic_stamp m (tp_cname tp)) as [sp|] eqn:ST.
    + simpl in Hpl. apply in_app_iff in Hpl. destruct Hpl as [Hpl|Hpl].
      * destruct (BASE pl Hpl) as (pa & ->). exists tp, pa; auto.
      * unfold stamp_stmts in Hpl. destruct (topic_stamp_from m (tp_cname tp)) as [[s0 sp']|]; simpl in Hpl;
        destruct Hpl as [<-|[<-|[]]]; eexists tp, _; repeat split; auto;
          apply expr_place_path_expr with (q := []); auto.
    + destruct (BASE pl Hpl) as (pa & ->). exists tp, pa; auto.
  - exfalso. simpl in F; destruct F as [E|[E|[]]]; inversion E; subst; clear E.
    + simpl in Hpl. rewrite assigned_places_seq, flat_map_app in Hpl.
      apply in_app_iff in Hpl; destruct Hpl as [Hpl|Hpl]; [|simpl in Hpl; tauto].
      apply in_flat_map in Hpl; destruct Hpl as (st & Hst & Hpl).
      apply in_flat_map in Hst; destruct Hst as (tp & _ & Hst).
      simpl in Hst; destruct Hst as [<-|[<-|[]]]; simpl in Hpl; tauto.
    + unfold main_function in Hpl; cbn [fn_body] in Hpl. unfold main_stmts in Hpl.
      rewrite assigned_places_seq in Hpl. apply in_flat_map in Hpl; destruct Hpl as (st & Hst & Hpl).
      rewrite !in_app_iff in Hst. destruct Hst as [Hst|[Hst|[Hst|Hst]]].
      * simpl in Hst; destruct Hst as [<-|[<-|[]]]; simpl in Hpl; tauto.
      * apply in_map_iff in Hst; destruct Hst as (tp & <- & _); simpl in Hpl; tauto.
      * apply in_map_iff in Hst; destruct Hst as (tp & <- & _); simpl in Hpl; tauto.
      * simpl in Hst; destruct Hst as [<-|[<-|[]]]; simpl in Hpl; tauto.
Qed.

(** The names after [Controller_U] and [Controller_Y] in the list of all
    names, all distinct from them. *)
Definition names_after_controller (m : node_model) : list ident :=
  map (fun tp => msg_var (tp_cname tp)) (subscribed m)
  ++ flat_map clock_names (timed m)
  ++ map (fun tp => callback_name (tp_cname tp)) (subscribed m)
  ++ [input_glue_name]
  ++ map (fun tp => output_glue_name (tp_cname tp)) (published m)
  ++ [loop_name; main_name]
  ++ local_names m.

Lemma names_split:
  forall m,
  global_names m ++ local_names m
  = ([ros_init_name; ros_ok_name; ros_spinOnce_name; ros_rate_sleep_name]
     ++ time_extern_names m ++ flat_map topic_extern_names (nm_topics m) ++ [init_name m; step_name m])
    ++ nm_in_var m :: nm_out_var m :: names_after_controller m.
Proof.
  intros m; unfold global_names, names_after_controller. rewrite <- !app_assoc. reflexivity.
Qed.

Lemma wf_controller_vars_fresh:
  forall m, wf_facts m ->
  nm_in_var m <> nm_out_var m
  /\ ~ In (nm_in_var m) (names_after_controller m)
  /\ ~ In (nm_out_var m) (names_after_controller m).
Proof.
  intros m W. generalize (wf_names_nodup m W); rewrite names_split; intros ND.
  generalize (NoDup_remove_2 _ _ _ ND); intros N1.
  generalize (NoDup_remove_2 _ _ _ (NoDup_remove_1 _ _ _ ND)); intros N2.
  rewrite in_app_iff in N1, N2. simpl in N1. intuition.
Qed.

Lemma msg_var_in_after:
  forall m tp, In tp (subscribed m) -> In (msg_var (tp_cname tp)) (names_after_controller m).
Proof.
  intros m tp H; unfold names_after_controller; apply in_or_app; left.
  apply in_map_iff; eauto.
Qed.

Lemma callback_name_in_after:
  forall m tp, In tp (subscribed m) -> In (callback_name (tp_cname tp)) (names_after_controller m).
Proof.
  intros m tp H; unfold names_after_controller; rewrite !in_app_iff; right; right; left.
  apply in_map_iff; eauto.
Qed.

Lemma clock_name_in_after:
  forall m tp x, In tp (timed m) -> In x (clock_names tp) -> In x (names_after_controller m).
Proof.
  intros m tp x H Hx; unfold names_after_controller; rewrite !in_app_iff; right; left.
  apply in_flat_map; eauto.
Qed.

Lemma cmd_var_in_after:
  forall m tp, In tp (published m) -> In (cmd_var (tp_cname tp)) (names_after_controller m).
Proof.
  intros m tp H; unfold names_after_controller, local_names; rewrite !in_app_iff.
  do 8 right. apply in_map_iff; eauto.
Qed.

(** Preservation: no generated function other than [input_glue] assigns
    (a part of) [Controller_U], except the callback of a topic that is
    not timed, which assigns exactly the leaves of its direct input
    relations (rule 4.16). *)
Theorem generate_inputs_written_only_by_input_glue:
  forall m p id f, generate m = OK p -> find_def p id = Some (Gfun (Internal f)) ->
  id <> input_glue_name ->
  forall pl, In pl (assigned_places (fn_body f)) ->
     (exists r path, pl = Some (r, path) /\ r <> Rvar (nm_in_var m))
  \/ (exists tp ir, In tp (subscribed m) /\ is_timed m (tp_cname tp) = false
                    /\ id = callback_name (tp_cname tp) /\ In ir (direct_of m (tp_cname tp))
                    /\ pl = Some (Rvar (nm_in_var m), PField (ir_input ir) :: ir_elem ir)).
Proof.
  intros m p id f H F Hid pl Hpl.
  assert (W: wf_facts m) by (apply wf_facts_intro, (generate_sound m p H)).
  destruct (wf_controller_vars_fresh m W) as (_ & NU & _).
  destruct (generate_assigned_places m p id f H F pl Hpl)
    as [(tp & pa & Htp & _ & ->)|[(tp & x & Htp & _ & Hx & ->)|[(tp & ir & Htp & Eid & Hir & ->)|[(x & pa & E & _)|[(tp & Htp & E & _)|(tp & pa & _ & _ & ->)]]]]].
  - left. exists (Rvar (msg_var (tp_cname tp))), pa; split; auto.
    intros E; inversion E. apply NU; rewrite <- H1; apply msg_var_in_after; auto.
  - left. exists (Rvar x), []; split; auto.
    intros E; inversion E. apply NU; rewrite <- H1; eapply clock_name_in_after; eauto.
  - right. exists tp, ir. repeat split; auto.
    apply direct_of_In in Hir as (_ & Et & D). unfold is_direct in D.
    apply andb_true_iff in D as [_ D]. apply negb_true_iff in D. rewrite <- Et; exact D.
  - congruence.
  - congruence.
  - left. exists (Rderef command_param), pa; split; auto; discriminate.
Qed.

(** The generated functions never assign (a part of) [Controller_Y]: only
    the controller does. *)
Theorem generate_outputs_not_written:
  forall m p id f, generate m = OK p -> find_def p id = Some (Gfun (Internal f)) ->
  forall pl, In pl (assigned_places (fn_body f)) ->
  exists r path, pl = Some (r, path) /\ r <> Rvar (nm_out_var m).
Proof.
  intros m p id f H F pl Hpl.
  assert (W: wf_facts m) by (apply wf_facts_intro, (generate_sound m p H)).
  destruct (wf_controller_vars_fresh m W) as (NUY & _ & NY).
  destruct (generate_assigned_places m p id f H F pl Hpl)
    as [(tp & pa & Htp & _ & ->)|[(tp & x & Htp & _ & Hx & ->)|[(tp & ir & Htp & _ & Hir & ->)|[(x & pa & _ & ->)|[(tp & Htp & _ & ->)|(tp & pa & _ & _ & ->)]]]]].
  - exists (Rvar (msg_var (tp_cname tp))), pa; split; auto.
    intros E; inversion E. apply NY; rewrite <- H1; apply msg_var_in_after; auto.
  - exists (Rvar x), []; split; auto.
    intros E; inversion E. apply NY; rewrite <- H1; eapply clock_name_in_after; eauto.
  - exists (Rvar (nm_in_var m)), (PField (ir_input ir) :: ir_elem ir); split; auto. intros E; inversion E; auto.
  - exists (Rvar (nm_in_var m)), (PField x :: pa); split; auto. intros E; inversion E; auto.
  - exists (Rvar (new_var (tp_cname tp))), []; split; auto.
    intros E; inversion E. apply NY; rewrite <- H1; eapply clock_name_in_after; eauto. simpl; auto.
  - exists (Rderef command_param), pa; split; auto; discriminate.
Qed.

(** Whether an expression / a statement takes the address of (a part of)
    the variable [x] (conservatively: any address of an unknown place). *)
Fixpoint expr_takes_addr (x : ident) (e : expr) : bool :=
  match e with
  | Eaddrof e1 _ =>
      match expr_place e1 with
      | Some (Rvar y, _) => ident_eqb x y
      | Some (Rderef _, _) => false
      | None => true
      end || expr_takes_addr x e1
  | Ederef e1 _ | Efield e1 _ _ | Ecast e1 _ => expr_takes_addr x e1
  | Eindex e1 e2 _ => expr_takes_addr x e1 || expr_takes_addr x e2
  | _ => false
  end.

Fixpoint stmt_takes_addr (x : ident) (s : statement) : bool :=
  match s with
  | Sassign l r => expr_takes_addr x l || expr_takes_addr x r
  | Sset _ e => expr_takes_addr x e
  | Scall _ f args => expr_takes_addr x f || existsb (expr_takes_addr x) args
  | Ssequence s1 s2 => stmt_takes_addr x s1 || stmt_takes_addr x s2
  | Sifthenelse c s1 s2 => expr_takes_addr x c || stmt_takes_addr x s1 || stmt_takes_addr x s2
  | Sloop s1 => stmt_takes_addr x s1
  | Sreturn (Some e) => expr_takes_addr x e
  | _ => false
  end.

Lemma stmt_takes_addr_seq:
  forall x l, stmt_takes_addr x (seq_of l) = existsb (stmt_takes_addr x) l.
Proof. induction l as [|s l IH]; simpl; auto. rewrite IH; auto. Qed.

Lemma expr_takes_addr_path:
  forall x ce p e, expr_takes_addr x (path_expr ce e p) = expr_takes_addr x e.
Proof.
  induction p as [|[f|i] p IH]; simpl; intros e; auto; rewrite IH; simpl; auto.
  apply orb_false_r.
Qed.

Lemma copy_takes_no_addr:
  forall x ce q r1 p1 r2 p2,
  expr_takes_addr x r1 = false -> expr_takes_addr x r2 = false ->
  stmt_takes_addr x (copy q (path_expr ce r1 p1) (path_expr ce r2 p2)) = false.
Proof. intros; simpl; rewrite !expr_takes_addr_path; rewrite H, H0; auto. Qed.

Lemma copies_take_no_addr:
  forall x qs ld ls,
  (forall d, In d ld -> expr_takes_addr x d = false) ->
  (forall s, In s ls -> expr_takes_addr x s = false) ->
  existsb (stmt_takes_addr x) (copies qs ld ls) = false.
Proof.
  induction qs as [|q qs IH]; intros [|d ld] [|s ls] Hd Hs; simpl; auto.
  rewrite (Hs s), (Hd d) by (simpl; auto); simpl. apply IH; intros; [apply Hd|apply Hs]; simpl; auto.
Qed.

(** The only addresses the generated code takes are those of the loop's
    local messages [c_cmd] (in [loop]) and of the callbacks (in [main]). *)
Theorem generate_addresses_taken:
  forall m p id f x, generate m = OK p -> find_def p id = Some (Gfun (Internal f)) ->
  stmt_takes_addr x (fn_body f) = true ->
     (exists tp, In tp (published m) /\ id = loop_name /\ x = cmd_var (tp_cname tp))
  \/ (exists tp, In tp (subscribed m) /\ id = main_name /\ x = callback_name (tp_cname tp)).
Proof.
  intros m p id f x H F T.
  apply find_def_build with (m := m) in F; auto.
  unfold build_defs in F; rewrite !in_app_iff in F.
  destruct F as [F|[F|[F|[F|[F|[F|[F|[F|F]]]]]]]].
  - exfalso; eapply ros_externals_not_internal; eauto.
  - apply in_flat_map in F; destruct F as (tp & _ & F).
    unfold topic_externals in F; destruct (tp_dir tp); simpl in F; intuition discriminate.
  - simpl in F; intuition discriminate.
  - apply in_map_iff in F; destruct F as (tp & E & _); discriminate.
  - exfalso; eapply clock_globals_not_internal; eauto.
  - exfalso. apply in_map_iff in F; destruct F as (tp & E & Htp); inversion E; subst; clear E.
    assert (BASE: stmt_takes_addr x (seq_of (map (leaf_copy (composites m) (Evar (msg_var (tp_cname tp)) (Tstruct (tp_msg tp)))
                                      (deref_param msg_param (tp_msg tp))) (read_leaves m tp))) = false).
    { rewrite stmt_takes_addr_seq. apply not_true_iff_false. intros T'. apply existsb_exists in T'.
      destruct T' as (st & Hst & T'). apply in_map_iff in Hst; destruct Hst as ([pa q] & <- & _).
      unfold leaf_copy in T'; simpl fst in T'; simpl snd in T'.
      rewrite copy_takes_no_addr in T'; auto; discriminate. }
    unfold callback_function in T. destruct (is_timed m (tp_cname tp)); cbn [fn_body] in T.
    + cbn [stmt_takes_addr] in T. rewrite BASE in T. simpl in T. discriminate.
    + destruct (direct_of m (tp_cname tp)) as [|ir0 ds] eqn:D; cbn [fn_body] in T; [congruence|].
      cbn [stmt_takes_addr] in T. rewrite BASE, orb_false_l, <- D, stmt_takes_addr_seq in T.
      apply existsb_exists in T.
      destruct T as (st & Hst & T). apply in_map_iff in Hst; destruct Hst as (ir & <- & _).
      unfold direct_copy, input_dst in T. rewrite copy_takes_no_addr in T; auto; discriminate.
  - exfalso. simpl in F; destruct F as [E|[]]; inversion E; subst; clear E.
    assert (BASE: stmt_takes_addr x (input_base m) = false).
    { unfold input_base. rewrite stmt_takes_addr_seq, copies_take_no_addr; auto.
      + intros d Hd. unfold gen_list_controller_expr_input_glue in Hd.
        apply in_map_iff in Hd; destruct Hd as (ir & <- & _). unfold input_dst; rewrite expr_takes_addr_path; auto.
      + intros s Hs. unfold gen_list_global_expr_input_glue in Hs.
        apply in_map_iff in Hs; destruct Hs as (ir & <- & _). unfold input_src.
        rewrite expr_takes_addr_path; auto. }
    rewrite input_glue_body in T. destruct (timed m) eqn:TM; [congruence|].
    cbn [stmt_takes_addr] in T. rewrite BASE in T. simpl in T.
    unfold timed_stmts in T. rewrite stmt_takes_addr_seq in T. apply existsb_exists in T.
    destruct T as (st & Hst & T).
    apply in_app_iff in Hst. destruct Hst as [Hst|Hst].
    { destruct (reads_age m); [destruct Hst as [<-|[]]; discriminate|contradiction]. }
    apply in_app_iff in Hst. destruct Hst as [Hst|Hst]; [|apply in_app_iff in Hst; destruct Hst as [Hst|Hst]].
    + apply in_map_iff in Hst. destruct Hst as (ir & <- & _). unfold fallback_stmt in T.
      destruct (find_assoc (ir_input ir) (nm_fallbacks m)) as [v|]; [|discriminate].
      destruct (timeout_of m (ir_topic ir)); [|discriminate].
      simpl in T. unfold input_dst in T. rewrite expr_takes_addr_path in T.
      destruct v; simpl in T; try discriminate;
        destruct (inrel_prim (make_tables m) ir); discriminate.
    + apply in_map_iff in Hst. destruct Hst as (dr & <- & _). unfold derived_stmt in T.
      destruct (dr_kind dr); discriminate.
    + apply in_map_iff in Hst. destruct Hst as (tp & <- & _). discriminate.
  - exfalso. apply in_map_iff in F; destruct F as (tp & E & Htp); inversion E; subst; clear E.
    rewrite output_glue_body in T. cbn [stmt_takes_addr] in T. apply orb_true_iff in T. destruct T as [T|T].
    2:{ unfold strings_stmts in T. rewrite stmt_takes_addr_seq in T.
        apply existsb_exists in T; destruct T as (st & Hst & T).
        apply in_map_iff in Hst; destruct Hst as (a & <- & _).
        unfold const_store in T; simpl in T; rewrite expr_takes_addr_path in T; simpl in T; discriminate. }
    unfold output_pre in T.
    destruct (topic_stamp m (tp_cname tp)) as [sp|]; [simpl in T; apply orb_true_iff in T; destruct T as [T|T]|].
    2:{ unfold stamp_stmts, stamp_sec_expr in T.
        destruct (topic_stamp_from m (tp_cname tp)) as [[s0 sp']|]; simpl in T;
        rewrite !expr_takes_addr_path in T; simpl in T; [discriminate|].
        destruct (time_is_ros2 (nm_msgs m)); discriminate. }
    all: unfold output_base in T; simpl in T; rewrite !stmt_takes_addr_seq in T;
    apply orb_true_iff in T; destruct T as [T|T].
    all: first
      [ apply existsb_exists in T; destruct T as (st & Hst & T);
        apply in_map_iff in Hst; destruct Hst as ([pa q] & <- & _);
        unfold leaf_zero in T; simpl in T; rewrite expr_takes_addr_path in T; simpl in T;
        destruct q; discriminate
      | rewrite copies_take_no_addr in T; [discriminate| |];
        [ intros d Hd; unfold gen_list_message_expr_output_glue in Hd;
          apply in_map_iff in Hd; destruct Hd as (o & <- & _); unfold output_dst;
          rewrite expr_takes_addr_path; auto
        | intros s Hs; unfold gen_list_controller_expr_output_glue in Hs;
          apply in_map_iff in Hs; destruct Hs as (o & <- & _); unfold output_src;
          rewrite expr_takes_addr_path; auto ] ].
  - simpl in F; destruct F as [E|[E|[]]]; inversion E; subst; clear E.
    + left. simpl in T. rewrite stmt_takes_addr_seq, existsb_app in T. simpl in T.
      rewrite orb_false_r in T.
      apply existsb_exists in T; destruct T as (st & Hst & T).
      apply in_flat_map in Hst; destruct Hst as (tp & Htp & Hst).
      unfold publish_stmts, cmd_addr in Hst; simpl in Hst.
      destruct Hst as [<-|[<-|[]]]; simpl in T; rewrite !orb_false_r in T;
        apply ident_eqb_true in T; eauto.
    + right. unfold main_function in T; cbn [fn_body] in T. unfold main_stmts in T.
      rewrite stmt_takes_addr_seq, !existsb_app in T. simpl in T.
      rewrite !orb_false_r in T. apply orb_true_iff in T; destruct T as [T|T].
      * apply existsb_exists in T; destruct T as (st & Hst & T).
        apply in_map_iff in Hst; destruct Hst as (tp & <- & Htp).
        unfold subscribe_stmt in T; simpl in T. rewrite !orb_false_r in T.
        apply ident_eqb_true in T; eauto.
      * exfalso. apply existsb_exists in T; destruct T as (st & Hst & T).
        apply in_map_iff in Hst; destruct Hst as (tp & <- & Htp). discriminate.
Qed.

(** Preservation: the address of [Controller_U] (and of [Controller_Y]) is
    never taken, so no write through a pointer reaches it. *)
Theorem generate_inputs_address_not_taken:
  forall m p id f, generate m = OK p -> find_def p id = Some (Gfun (Internal f)) ->
  stmt_takes_addr (nm_in_var m) (fn_body f) = false
  /\ stmt_takes_addr (nm_out_var m) (fn_body f) = false.
Proof.
  intros m p id f H F.
  assert (W: wf_facts m) by (apply wf_facts_intro, (generate_sound m p H)).
  destruct (wf_controller_vars_fresh m W) as (_ & NU & NY).
  assert (G: forall x, ~ In x (names_after_controller m) -> stmt_takes_addr x (fn_body f) = false).
  { intros x Nx. destruct (stmt_takes_addr x (fn_body f)) eqn:T; auto. exfalso.
    destruct (generate_addresses_taken m p id f x H F T) as [(tp & Htp & _ & E)|(tp & Htp & _ & E)];
      apply Nx; rewrite E; [apply cmd_var_in_after|apply callback_name_in_after]; auto. }
  split; apply G; auto.
Qed.
