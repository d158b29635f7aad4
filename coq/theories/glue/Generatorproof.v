(** * Properties of the glue-code generator: T4, the shape of the program, relation consistency *)

(** This file proves, for every node model:
    - T4: [generate] accepts exactly the well-formed models
      ([generate_complete], [generate_sound]), and [wf_check] is [wf]
      with error messages ([wf_check_wf]);
    - the shape of the generated program: distinct global names, the
      function found under each generated name and its body
      ([generate_callback], [generate_input_glue], [generate_output_glue],
      [generate_loop], [generate_main]);
    - the first of T3, the paper's Section 6 properties: relation
      consistency ([relation_consistency_input_glue],
      [relation_consistency_output_glue], Figure 15).
    The rest of T3 (valid assignment via type checking, Figure 16, and
    preservation) is in [Assignproof].  The facts about models that these
    proofs use (what well-formedness gives, the lookup tables, the leaves
    of a message, the typing of accesses) are in [Generatorspec]. *)

From Coq Require Import String Ascii List ZArith Bool Lia.
From ROSGen Require Import Errors Syntax Values Operators Maps NodeModel Wellformed Generator Generatorspec.
Import ListNotations.

Local Open Scope string_scope.
Local Open Scope list_scope.
Local Open Scope error_monad_scope.

(** ** T4: [wf_check] is [wf], and [generate] accepts exactly the well-formed models *)

Lemma ftype_check_ok:
  forall md seen t, ftype_check md seen t = OK tt <-> ftype_ok seen t = true.
Proof.
  induction t as [q|id|t IH n]; simpl.
  - tauto.
  - apply assertion_ok.
  - rewrite bind_unit_ok, assertion_ok, IH, !andb_true_iff; tauto.
Qed.

Lemma msgdef_check_ok:
  forall seen md, msgdef_check seen md = OK tt <-> msgdef_ok seen md = true.
Proof.
  intros; unfold msgdef_check, msgdef_ok.
  rewrite !bind_unit_ok, assertion_ok, check_nodup_ok, !andb_true_iff.
  rewrite (check_all_ok _ _ (fun ft => ftype_ok seen (snd ft))) by (intros; apply ftype_check_ok).
  tauto.
Qed.

Lemma msgs_check_ok:
  forall msgs seen, msgs_check seen msgs = OK tt <-> msgs_ok seen msgs = true.
Proof.
  induction msgs as [|md msgs IH]; simpl; intros seen.
  - tauto.
  - rewrite bind_unit_ok, andb_true_iff, msgdef_check_ok, IH; tauto.
Qed.

Lemma topic_check_ok:
  forall msgs tp, topic_check msgs tp = OK tt <-> topic_ok msgs tp = true.
Proof.
  intros; unfold topic_check, topic_ok.
  rewrite !bind_unit_ok, !assertion_ok, !andb_true_iff.
  destruct (find_msg msgs (tp_msg tp)); intuition congruence.
Qed.

Lemma inrel_check_ok:
  forall m tb ir, inrel_check m tb ir = OK tt <-> inrel_ok m tb ir = true.
Proof.
  intros; unfold inrel_check, inrel_ok.
  destruct (lookup_topic tb (ir_topic ir)) as [tp|]; [|split; discriminate].
  rewrite bind_unit_ok, assertion_ok, andb_true_iff.
  destruct (tget (enc_string (ir_input ir)) (tb_inputs tb)) as [t|]; [|intuition discriminate].
  destruct (ctrl_prim t (ir_elem ir)) as [q|]; [|intuition discriminate].
  destruct (resolve_prim (nm_msgs m) (FTmsg (tp_msg tp)) (ir_path ir)) as [q'|];
    [rewrite assertion_ok|]; intuition discriminate.
Qed.

Lemma outrel_check_ok:
  forall m tb o, outrel_check m tb o = OK tt <-> outrel_ok m tb o = true.
Proof.
  intros; unfold outrel_check, outrel_ok.
  destruct (tget (enc_string (or_output o)) (tb_outputs tb)) as [t|]; [|split; discriminate].
  destruct (ctrl_prim t (or_elem o)) as [q|]; [|split; discriminate].
  destruct (lookup_topic tb (or_topic o)) as [tp|]; [|split; discriminate].
  rewrite bind_unit_ok, assertion_ok, andb_true_iff.
  destruct (resolve_prim (nm_msgs m) (FTmsg (tp_msg tp)) (or_path o)) as [q'|];
    [rewrite assertion_ok|]; intuition discriminate.
Qed.

Lemma bind_unit_iff:
  forall (a b : res unit) (A B : Prop),
  (a = OK tt <-> A) -> (b = OK tt <-> B) -> ((do _ <- a; b) = OK tt <-> A /\ B).
Proof. intros a b A B HA HB; rewrite bind_unit_ok, HA, HB; tauto. Qed.

Lemma check_all_iff:
  forall (A : Type) (f : A -> res unit) (g : A -> bool) l,
  (forall x, f x = OK tt <-> g x = true) -> (check_all f l = OK tt <-> forallb g l = true).
Proof. intros; apply check_all_ok; auto. Qed.

Ltac wf_rule :=
  first [ apply assertion_ok | apply check_nodup_ok | apply check_nodup_keys_ok | apply msgs_check_ok
        | apply check_all_iff; intros;
          first [ apply assertion_ok | apply topic_check_ok | apply inrel_check_ok
                | apply outrel_check_ok ] ].

(** The checker that names the culprit agrees with the boolean rules. *)
Theorem wf_check_wf: forall m, wf_check m = OK tt <-> wf m = true.
Proof.
  intros m; unfold wf, wf_check, check_ident; cbv zeta.
  eapply iff_trans; [repeat (apply bind_unit_iff; [wf_rule|]); wf_rule|].
  rewrite !andb_true_iff. tauto.
Qed.

Lemma generate_inv: forall m p, generate m = OK p -> wf m = true /\ p = build_program m.
Proof.
  unfold generate; intros m p H.
  destruct (wf_check m) as [[]|e] eqn:E; simpl in H; [|discriminate].
  inversion H; split; auto. apply wf_check_wf; auto.
Qed.

(** T4, completeness: every well-formed model is accepted. *)
Theorem generate_complete: forall m, wf m = true -> exists p, generate m = OK p.
Proof.
  intros m H; exists (build_program m); unfold generate.
  apply wf_check_wf in H; rewrite H; reflexivity.
Qed.

(** T4, soundness: every accepted model is well formed. *)
Theorem generate_sound: forall m p, generate m = OK p -> wf m = true.
Proof. intros m p H; apply (generate_inv m p H). Qed.

(** An ill-formed model is refused with an error message. *)
Theorem generate_refuses: forall m, wf m = false -> exists msg, generate m = Error msg.
Proof.
  intros m H; unfold generate. destruct (wf_check m) as [[]|e] eqn:E.
  - apply wf_check_wf in E; congruence.
  - exists e; reflexivity.
Qed.

(** ** The generated program *)

Lemma map_fst_flat_map:
  forall (A : Type) (f : A -> list (ident * globdef)) l,
  map fst (flat_map f l) = flat_map (fun x => map fst (f x)) l.
Proof. induction l as [|x l IH]; simpl; auto. rewrite map_app, IH; auto. Qed.

Lemma topic_externals_names: forall tp, map fst (topic_externals tp) = topic_extern_names tp.
Proof. intros tp; unfold topic_externals, topic_extern_names; destruct (tp_dir tp); auto. Qed.

(** The global names of [build_defs] are [global_names]. *)
Lemma build_defs_names: forall m, map fst (build_defs m (make_tables m)) = global_names m.
Proof.
  intros m; unfold build_defs, global_names, ros_externals.
  rewrite !map_app, map_fst_flat_map, !map_map, <- !app_assoc.
  replace (map fst (time_externals m)) with (time_extern_names m)
    by (unfold time_externals, time_extern_names, now_externals, stamp_externals,
          now_extern_names, stamp_extern_names;
        rewrite map_app; destruct (timed m), (nm_stamps m); reflexivity).
  replace (map fst (flat_map clock_globals (timed m))) with (flat_map clock_names (timed m))
    by (rewrite map_fst_flat_map; reflexivity).
  replace (flat_map (fun x => map fst (topic_externals x)) (nm_topics m))
    with (flat_map topic_extern_names (nm_topics m)); [reflexivity|].
  induction (nm_topics m) as [|tp l IH]; simpl; auto. rewrite IH, topic_externals_names; auto.
Qed.

Lemma wf_globals_nodup: forall m, wf_facts m -> NoDup (global_names m).
Proof.
  intros m W. generalize (wf_names_nodup m W); intros ND. apply NoDup_app_inv in ND; tauto.
Qed.

Lemma generate_types: forall m p, generate m = OK p -> prog_types p = composites m.
Proof. intros m p H; apply generate_inv in H; destruct H as [_ ->]; auto. Qed.

Lemma generate_defs: forall m p, generate m = OK p -> prog_defs p = build_defs m (make_tables m).
Proof. intros m p H; apply generate_inv in H; destruct H as [_ ->]; auto. Qed.

(** All global names of the generated program are distinct. *)
Theorem generate_names_distinct:
  forall m p, generate m = OK p -> NoDup (map fst (prog_defs p)).
Proof.
  intros m p H. rewrite (generate_defs m p H), build_defs_names.
  apply wf_globals_nodup, wf_facts_intro, (generate_sound m p H).
Qed.

(** No parameter, temporary or local variable of a generated function has
    the name of a global. *)
Theorem generate_locals_fresh:
  forall m p x, generate m = OK p -> In x (local_names m) -> ~ In x (map fst (prog_defs p)).
Proof.
  intros m p x H Hx Hg. rewrite (generate_defs m p H), build_defs_names in Hg.
  generalize (wf_names_nodup m (wf_facts_intro m (generate_sound m p H))).
  intros ND; apply NoDup_app_inv in ND; destruct ND as (_ & _ & D). eapply D; eauto.
Qed.

Lemma generate_find_def:
  forall m p id d, generate m = OK p -> In (id, d) (build_defs m (make_tables m)) -> find_def p id = Some d.
Proof.
  intros m p id d H Hin. unfold find_def. apply In_find_assoc.
  - apply (generate_names_distinct m p H).
  - rewrite (generate_defs m p H); auto.
Qed.

Lemma find_def_build:
  forall m p id d, generate m = OK p -> find_def p id = Some d -> In (id, d) (build_defs m (make_tables m)).
Proof.
  intros m p id d H F. unfold find_def in F. apply find_assoc_In in F.
  rewrite (generate_defs m p H) in F; auto.
Qed.

Lemma in_build_defs_externals:
  forall m id d, In (id, d) (ros_externals m ++ flat_map topic_externals (nm_topics m) ++ controller_defs m) ->
  In (id, d) (build_defs m (make_tables m)).
Proof.
  intros m id d H; unfold build_defs. rewrite !in_app_iff in *; tauto.
Qed.

Lemma in_subscribed: forall m tp, In tp (subscribed m) <-> In tp (nm_topics m) /\ tp_dir tp = Subscribe.
Proof.
  intros m tp; unfold subscribed, is_subscribed; rewrite filter_In.
  destruct (tp_dir tp); simpl; intuition congruence.
Qed.

Lemma in_published: forall m tp, In tp (published m) <-> In tp (nm_topics m) /\ tp_dir tp = Publish.
Proof.
  intros m tp; unfold published, is_published; rewrite filter_In.
  destruct (tp_dir tp); simpl; intuition congruence.
Qed.

(** The external functions and global variables, under their names. *)
Theorem generate_externals:
  forall m p, generate m = OK p ->
     find_def p ros_init_name = Some (Gfun (External EF_ros_init [] Tvoid))
  /\ find_def p ros_ok_name = Some (Gfun (External EF_ros_ok [] tint))
  /\ find_def p ros_spinOnce_name = Some (Gfun (External EF_ros_spinOnce [] Tvoid))
  /\ find_def p ros_rate_sleep_name = Some (Gfun (External (EF_ros_rate_sleep (nm_period_ms m)) [] Tvoid))
  /\ find_def p (init_name m)
     = Some (Gfun (External (EF_controller_initialize (nm_in_var m) (nm_out_var m)) [] Tvoid))
  /\ find_def p (step_name m)
     = Some (Gfun (External (EF_controller_step (nm_in_var m) (nm_out_var m)) [] Tvoid))
  /\ find_def p (nm_in_var m) = Some (Gvar (Tstruct (nm_in_struct m)))
  /\ find_def p (nm_out_var m) = Some (Gvar (Tstruct (nm_out_struct m))).
Proof.
  intros m p H.
  repeat split; apply (generate_find_def m p _ _ H); apply in_build_defs_externals;
    rewrite !in_app_iff; simpl; tauto.
Qed.

(** A node that stamps messages declares the time functions. *)
Theorem generate_time_externals:
  forall m p, generate m = OK p -> nm_stamps m <> [] ->
     find_def p ros_time_sec_name = Some (Gfun (External EF_ros_time_sec [] tuint))
  /\ find_def p ros_time_nsec_name = Some (Gfun (External EF_ros_time_nsec [] tuint)).
Proof.
  intros m p H NE. split; apply (generate_find_def m p _ _ H), in_build_defs_externals;
    rewrite !in_app_iff; left; unfold ros_externals, time_externals, stamp_externals;
    (destruct (nm_stamps m); [contradiction|]); rewrite !in_app_iff; simpl; tauto.
Qed.

(** A node with a timed topic declares [ros_now], and the clock globals
    of each timed topic (rule 4.12). *)
Theorem generate_now_external:
  forall m p, generate m = OK p -> timed m <> [] ->
  find_def p ros_now_name = Some (Gfun (External EF_ros_now [] (Tlong Unsigned))).
Proof.
  intros m p H NE. apply (generate_find_def m p _ _ H), in_build_defs_externals.
  rewrite !in_app_iff; left; unfold ros_externals, time_externals, now_externals.
  destruct (timed m); [contradiction|]. rewrite !in_app_iff; simpl; tauto.
Qed.

Theorem generate_clock_globals:
  forall m p tp, generate m = OK p -> In tp (timed m) ->
     find_def p (time_var (tp_cname tp)) = Some (Gvar (Tlong Unsigned))
  /\ find_def p (new_var (tp_cname tp)) = Some (Gvar (Tint I8 Unsigned))
  /\ find_def p (rcvd_var (tp_cname tp)) = Some (Gvar (Tint I8 Unsigned)).
Proof.
  intros m p tp H Htp.
  assert (E: forall id d, In (id, d) (clock_globals tp) -> find_def p id = Some d).
  { intros id d Hin. apply (generate_find_def m p _ _ H). unfold build_defs; rewrite !in_app_iff.
    do 4 right; left. apply in_flat_map; eauto. }
  repeat split; apply E; simpl; auto.
Qed.

Theorem generate_topic_externals:
  forall m p tp, generate m = OK p -> In tp (nm_topics m) ->
  match tp_dir tp with
  | Subscribe =>
      find_def p (subscribe_name (tp_cname tp))
      = Some (Gfun (External (EF_ros_subscribe (tp_name tp) (tp_msg tp) (tp_queue tp))
                             [tptr (callback_type (tp_msg tp))] Tvoid))
  | Publish =>
      find_def p (advertise_name (tp_cname tp))
      = Some (Gfun (External (EF_ros_advertise (tp_name tp) (tp_msg tp) (tp_queue tp)) [] Tvoid))
   /\ find_def p (publish_name (tp_cname tp))
      = Some (Gfun (External (EF_ros_publish (tp_name tp) (tp_msg tp))
                             [tptr (Tstruct (tp_msg tp))] Tvoid))
  end.
Proof.
  intros m p tp H Htp.
  assert (E: forall id d, In (id, d) (topic_externals tp) -> find_def p id = Some d).
  { intros id d Hin. apply (generate_find_def m p _ _ H), in_build_defs_externals.
    rewrite !in_app_iff; right; left. apply in_flat_map; eauto. }
  unfold topic_externals in E. destruct (tp_dir tp); [|split]; apply E; simpl; auto.
Qed.

(** Temporaries. *)
Lemma temps_of_find:
  forall q qs, In q qs -> find_assoc (temp_name q) (temps_of qs) = Some (ctype_of_prim q).
Proof.
  intros q qs Hin. unfold temps_of. apply find_assoc_filter.
  - destruct q; reflexivity.
  - simpl. apply existsb_exists; exists q; split; auto. apply ident_eqb_refl.
Qed.

Lemma NoDup_map_filter:
  forall (A B : Type) (f : A -> B) (P : A -> bool) l, NoDup (map f l) -> NoDup (map f (filter P l)).
Proof.
  induction l as [|a l IH]; simpl; intros ND; auto.
  inversion ND as [|? ? Hn ND']; subst.
  destruct (P a); simpl; auto. constructor; auto.
  intros Hin; apply Hn. apply in_map_iff in Hin; destruct Hin as (b & E & Hb).
  apply filter_In in Hb. rewrite <- E; apply in_map; tauto.
Qed.

Lemma temps_of_names: forall qs x, In x (map fst (temps_of qs)) -> In x (map fst all_temps).
Proof.
  intros qs x H. unfold temps_of in H. apply in_map_iff in H. destruct H as (xt & <- & Hx).
  apply filter_In in Hx. apply in_map; tauto.
Qed.

Lemma temps_of_nodup: forall qs, NoDup (map fst (temps_of qs)).
Proof.
  intros qs. unfold temps_of. apply NoDup_map_filter.
  repeat constructor; simpl; intuition discriminate.
Qed.

(** Callbacks: for each subscribed topic, [c_callback] copies the leaves
    of [*msg] that the glue keeps ([read_leaves]) into the global
    [c_msg], in the order of [leaves]; then, for a topic that is not
    timed and has direct input relations (rule 4.16), it copies their
    leaves into [Controller_U], in model order. *)
Theorem generate_callback:
  forall m p tp, generate m = OK p -> In tp (subscribed m) ->
  let c := tp_cname tp in
  let M := tp_msg tp in
  find_def p (msg_var c) = Some (Gvar (Tstruct M))
  /\ exists f,
     find_def p (callback_name c) = Some (Gfun (Internal f))
  /\ fn_return f = Tvoid
  /\ fn_params f = [(msg_param, tptr (Tstruct M))]
  /\ fn_vars f = []
  /\ fn_body f = (let base := seq_of (map (leaf_copy (prog_types p) (Evar (msg_var c) (Tstruct M))
                                                                (deref_param msg_param M))
                                        (read_leaves m tp)) in
                  if is_timed m c then Ssequence base (clock_stmts c)
                  else match direct_of m c with
                       | [] => base
                       | ds => Ssequence base (seq_of (map (direct_copy m (make_tables m) M) ds))
                       end)
  /\ NoDup (map fst (fn_temps f))
  /\ (forall l, In l (read_leaves m tp) ->
        find_assoc (temp_name (snd l)) (fn_temps f) = Some (ctype_of_prim (snd l)))
  /\ (is_timed m c = false -> forall ir, In ir (direct_of m c) ->
        find_assoc (temp_name (inrel_prim (make_tables m) ir)) (fn_temps f)
        = Some (ctype_of_prim (inrel_prim (make_tables m) ir)))
  /\ (is_timed m c = true -> find_assoc (temp_name Puint64) (fn_temps f) = Some (Tlong Unsigned)).
Proof.
  intros m p tp H Hin; cbv zeta. rewrite (generate_types m p H). split.
  - apply (generate_find_def m p _ _ H). unfold build_defs; rewrite !in_app_iff.
    do 3 right; left. change (msg_var (tp_cname tp), Gvar (Tstruct (tp_msg tp))) with (msg_global tp). apply in_map; auto.
  - exists (callback_function m (make_tables m) tp); split.
    { apply (generate_find_def m p _ _ H). unfold build_defs; rewrite !in_app_iff.
      do 5 right; left. change (callback_name (tp_cname tp), Gfun (Internal (callback_function m (make_tables m) tp)))
        with (callback_def m (make_tables m) tp). apply in_map; auto. }
    unfold callback_function; destruct (is_timed m (tp_cname tp)) eqn:T;
      [|destruct (direct_of m (tp_cname tp)) as [|ir0 ds] eqn:D]; simpl; repeat split.
    + apply temps_of_nodup.
    + intros l Hl. apply temps_of_find. right. apply in_map; auto.
    + intros E; discriminate.
    + intros _. apply (temps_of_find Puint64). left; auto.
    + apply temps_of_nodup.
    + intros l Hl. apply temps_of_find. apply in_map; auto.
    + intros _ ir [].
    + intros E; discriminate.
    + apply temps_of_nodup.
    + intros l Hl. apply temps_of_find. apply in_or_app; left; apply in_map; auto.
    + intros _ ir Hir. apply temps_of_find. apply in_or_app; right. change (In (inrel_prim (make_tables m) ir) (map (inrel_prim (make_tables m)) (ir0 :: ds))). apply in_map; auto.
    + intros E; discriminate.
Qed.

(** ** Relation consistency (the paper's Figure 15) *)

(** The lists of source and destination expressions of the copies of
    [input_glue], one per input relation. *)
Definition gen_list_global_expr_input_glue (m : node_model) (lir : list inrel) : list expr :=
  map (input_src m (make_tables m)) lir.
Definition gen_list_controller_expr_input_glue (m : node_model) (lir : list inrel) : list expr :=
  map (input_dst m) lir.

(** The sequence of copies [d1 = s1; d2 = s2; ...] through the temporaries
    of the primitives [qs]. *)
Fixpoint copies (qs : list prim) (ld ls : list expr) : list statement :=
  match qs, ld, ls with
  | q :: qs', d :: ld', s :: ls' => copy q d s :: copies qs' ld' ls'
  | _, _, _ => []
  end.

(** Relation consistency: the [i]-th source expression designates the leaf
    of the [i]-th relation in the global message of its topic, and the
    [i]-th destination designates its controller input field. *)
Inductive relation_consistency_input (m : node_model) : list inrel -> list expr -> list expr -> Prop :=
  | rci_nil:
      relation_consistency_input m [] [] []
  | rci_cons: forall ir lir g lg c lc,
      expr_place g = Some (Rvar (msg_var (ir_topic ir)), ir_path ir) ->
      expr_place c = Some (Rvar (nm_in_var m), PField (ir_input ir) :: ir_elem ir) ->
      relation_consistency_input m lir lg lc ->
      relation_consistency_input m (ir :: lir) (g :: lg) (c :: lc).

Theorem relation_consistency_input_glue:
  forall m lir lg lc,
  lg = gen_list_global_expr_input_glue m lir ->
  lc = gen_list_controller_expr_input_glue m lir ->
  relation_consistency_input m lir lg lc.
Proof.
  intros m lir lg lc -> ->. induction lir as [|ir lir IH]; simpl; constructor; auto;
    apply expr_place_path_expr with (q := []); auto.
Qed.

(** The copies of the relations, in order: [Controller_U.In_i =
    c_i_msg.path_i] through a temporary. *)
Definition input_base (m : node_model) : statement :=
  seq_of (copies (map (inrel_prim (make_tables m)) (glue_inrels m))
                 (gen_list_controller_expr_input_glue m (glue_inrels m))
                 (gen_list_global_expr_input_glue m (glue_inrels m))).

(** The body of [input_glue]: the copies, then, if some topic is timed,
    the freshness (rule 4.12). *)
Lemma input_glue_body:
  forall m,
  fn_body (input_glue_function m (make_tables m))
  = match timed m with
    | [] => input_base m
    | _ :: _ => Ssequence (input_base m) (timed_stmts m (make_tables m))
    end.
Proof.
  intros m. assert (E: seq_of (map (input_copy m (make_tables m)) (glue_inrels m)) = input_base m).
  { unfold input_base; f_equal. unfold gen_list_controller_expr_input_glue, gen_list_global_expr_input_glue.
    induction (glue_inrels m) as [|ir l IH]; simpl; auto. rewrite IH; auto. }
  unfold input_glue_function; destruct (timed m); simpl; rewrite E; auto.
Qed.

(** The same for one published topic with C name [c] and message [M]. *)
Definition gen_list_controller_expr_output_glue (m : node_model) (lor : list outrel) : list expr :=
  map (output_src m) lor.
Definition gen_list_message_expr_output_glue (m : node_model) (M : ident) (lor : list outrel) : list expr :=
  map (output_dst m M) lor.

Inductive relation_consistency_output (m : node_model) (c : ident) :
    list outrel -> list expr -> list expr -> Prop :=
  | rco_nil:
      relation_consistency_output m c [] [] []
  | rco_cons: forall o lor s ls d ld,
      or_topic o = c ->
      expr_place s = Some (Rvar (nm_out_var m), PField (or_output o) :: or_elem o) ->
      expr_place d = Some (Rderef command_param, or_path o) ->
      relation_consistency_output m c lor ls ld ->
      relation_consistency_output m c (o :: lor) (s :: ls) (d :: ld).

Theorem relation_consistency_output_glue:
  forall m c M lor ls ld,
  lor = topic_outrels (make_tables m) c ->
  ls = gen_list_controller_expr_output_glue m lor ->
  ld = gen_list_message_expr_output_glue m M lor ->
  relation_consistency_output m c lor ls ld.
Proof.
  intros m c M lor ls ld Hl -> ->.
  assert (Hc: forall o, In o lor -> or_topic o = c).
  { intros o Ho; subst lor. apply In_topic_outrels in Ho; tauto. }
  clear Hl. induction lor as [|o lor IH]; simpl; constructor; auto with datatypes;
    apply expr_place_path_expr with (q := []); auto.
Qed.

(** The zeroing and the copies of [output_glue_c]. *)
Definition output_base (m : node_model) (tp : topic) : statement :=
  let M := tp_msg tp in
  let lor := topic_outrels (make_tables m) (tp_cname tp) in
  Ssequence
    (seq_of (map (leaf_zero (composites m) (deref_param command_param M)) (leaves (nm_msgs m) M)))
    (seq_of (copies (map (outrel_prim (make_tables m)) lor)
                    (gen_list_message_expr_output_glue m M lor)
                    (gen_list_controller_expr_output_glue m lor))).

Lemma output_copies_eq:
  forall m M l,
  seq_of (map (output_copy m (make_tables m) M) l)
  = seq_of (copies (map (outrel_prim (make_tables m)) l)
                   (gen_list_message_expr_output_glue m M l)
                   (gen_list_controller_expr_output_glue m l)).
Proof.
  intros m M l. unfold gen_list_controller_expr_output_glue, gen_list_message_expr_output_glue.
  induction l as [|o l IH]; simpl; auto. rewrite IH; auto.
Qed.

(** The zeroing, the copies and the stamp if the topic has one. *)
Definition output_pre (m : node_model) (tp : topic) : statement :=
  match topic_stamp m (tp_cname tp) with
  | None => output_base m tp
  | Some sp => Ssequence (output_base m tp) (stamp_stmts m (make_tables m) (tp_cname tp) (tp_msg tp) sp)
  end.

(** The body of [output_glue_c]: zero every leaf of [*command], then the
    copies of the topic's output relations, in order, then the stamp if
    the topic has one, then the constant strings. *)
Lemma output_glue_body:
  forall m tp,
  fn_body (output_glue_function m (make_tables m) tp)
  = Ssequence (output_pre m tp) (strings_stmts m (tp_cname tp) (tp_msg tp)).
Proof.
  intros m tp. unfold output_glue_function, output_pre, output_base.
  destruct (topic_stamp m (tp_cname tp)); simpl; rewrite output_copies_eq; reflexivity.
Qed.

(** The copy of an input relation, concretely. *)
Lemma input_exprs:
  forall m ir, wf_facts m -> In ir (nm_inrels m) ->
  exists tp t q,
     find_topic (nm_topics m) (ir_topic ir) = Some tp
  /\ tp_cname tp = ir_topic ir
  /\ In tp (subscribed m)
  /\ find_assoc (ir_input ir) (nm_inputs m) = Some t
  /\ ctrl_prim t (ir_elem ir) = Some q
  /\ resolve (nm_msgs m) (FTmsg (tp_msg tp)) (ir_path ir) = Some (FTprim q)
  /\ inrel_prim (make_tables m) ir = q
  /\ input_src m (make_tables m) ir = path_expr (composites m) (Evar (msg_var (ir_topic ir)) (Tstruct (tp_msg tp))) (ir_path ir)
  /\ input_dst m ir = path_expr (composites m) (Evar (nm_in_var m) (Tstruct (nm_in_struct m))) (PField (ir_input ir) :: ir_elem ir).
Proof.
  intros m ir W Hin. destruct (wf_inrel m ir W Hin) as (tp & t & q & F & S & I & Q & R).
  exists tp, t, q. destruct (find_topic_In _ _ _ F) as [Htp Ec].
  repeat split; auto.
  - apply in_subscribed; split; auto. unfold is_subscribed in S.
    destruct (tp_dir tp); auto; discriminate.
  - eapply input_prim_tables; eauto.
  - unfold input_src. rewrite (topic_msg_tables m _ _ F); auto.
Qed.

(** The copy of an output relation of a published topic, concretely. *)
Lemma output_exprs:
  forall m tp o, wf_facts m -> In tp (nm_topics m) -> In o (topic_outrels (make_tables m) (tp_cname tp)) ->
  exists t q,
     In o (nm_outrels m)
  /\ or_topic o = tp_cname tp
  /\ tp_dir tp = Publish
  /\ find_assoc (or_output o) (nm_outputs m) = Some t
  /\ ctrl_prim t (or_elem o) = Some q
  /\ resolve (nm_msgs m) (FTmsg (tp_msg tp)) (or_path o) = Some (FTprim q)
  /\ outrel_prim (make_tables m) o = q
  /\ output_src m o = path_expr (composites m) (Evar (nm_out_var m) (Tstruct (nm_out_struct m))) (PField (or_output o) :: or_elem o)
  /\ output_dst m (tp_msg tp) o = path_expr (composites m) (deref_param command_param (tp_msg tp)) (or_path o).
Proof.
  intros m tp o W Htp Ho. apply In_topic_outrels in Ho. destruct Ho as [Hin E].
  destruct (wf_outrel m o W Hin) as (tp' & t & q & F & S & O & Q & R).
  rewrite E, (In_find_topic _ _ (wf_cnames_nodup m W) Htp) in F. inversion F; subst tp'.
  exists t, q; repeat split; auto.
  - unfold is_published in S; destruct (tp_dir tp); auto; discriminate.
  - eapply output_prim_tables; eauto.
Qed.

(** [input_glue]: the copies of the input relations that are not direct
    (rule 4.16), in order. *)
Theorem generate_input_glue:
  forall m p, generate m = OK p ->
  exists f,
     find_def p input_glue_name = Some (Gfun (Internal f))
  /\ fn_return f = Tvoid /\ fn_params f = [] /\ fn_vars f = []
  /\ fn_body f = match timed m with
                 | [] => input_base m
                 | _ :: _ => Ssequence (input_base m) (timed_stmts m (make_tables m))
                 end
  /\ NoDup (map fst (fn_temps f))
  /\ (forall ir, In ir (glue_inrels m) ->
        find_assoc (temp_name (inrel_prim (make_tables m) ir)) (fn_temps f)
        = Some (ctype_of_prim (inrel_prim (make_tables m) ir)))
  /\ (timed m <> [] ->
        (reads_age m = true ->
           find_assoc now_temp (fn_temps f) = Some (Tlong Unsigned)
        /\ find_assoc age_temp (fn_temps f) = Some (Tlong Unsigned))
     /\ (reads_flag m = true -> find_assoc (temp_name Pbool) (fn_temps f) = Some (ctype_of_prim Pbool))).
Proof.
  intros m p H. exists (input_glue_function m (make_tables m)).
  refine (conj _ (conj _ (conj _ (conj _ (conj _ (conj _ (conj _ _))))))).
  - apply (generate_find_def m p _ _ H). unfold build_defs; rewrite !in_app_iff.
    do 6 right; left; simpl; auto.
  - unfold input_glue_function; destruct (timed m); reflexivity.
  - unfold input_glue_function; destruct (timed m); reflexivity.
  - unfold input_glue_function; destruct (timed m); reflexivity.
  - apply input_glue_body.
  - unfold input_glue_function; destruct (timed m) eqn:T; cbn [fn_temps].
    + apply temps_of_nodup.
    + unfold timed_temps. destruct (reads_age m); cbn [app].
      * constructor; [|constructor].
        -- cbn [map fst]. intros [E|E]; [discriminate|].
           apply temps_of_names in E. simpl in E. intuition discriminate.
        -- cbn [map fst]. intros E.
           apply temps_of_names in E. simpl in E. intuition discriminate.
        -- apply temps_of_nodup.
      * apply temps_of_nodup.
  - unfold input_glue_function; destruct (timed m) eqn:T; cbn [fn_temps].
    + intros ir Hir. apply temps_of_find. apply in_map_iff; eauto.
    + intros ir Hir. unfold timed_temps. rewrite find_assoc_app_right.
      * apply temps_of_find. apply in_app_iff; right; apply in_map_iff; eauto.
      * destruct (reads_age m); [|simpl; auto].
        destruct (inrel_prim (make_tables m) ir); simpl; intuition discriminate.
  - unfold input_glue_function; destruct (timed m) eqn:T; cbn [fn_temps].
    + intros; congruence.
    + intros _. unfold timed_temps. split.
      * intros ->. split; reflexivity.
      * intros ->. rewrite find_assoc_app_right.
        -- apply (temps_of_find Pbool). left; auto.
        -- destruct (reads_age m); simpl; intuition discriminate.
Qed.

(** [output_glue_c]: zero the message, then the copies of the topic's
    output relations, in order. *)
Theorem generate_output_glue:
  forall m p tp, generate m = OK p -> In tp (published m) ->
  let c := tp_cname tp in
  let M := tp_msg tp in
  let lor := topic_outrels (make_tables m) c in
  exists f,
     find_def p (output_glue_name c) = Some (Gfun (Internal f))
  /\ fn_return f = Tvoid
  /\ fn_params f = [(command_param, tptr (Tstruct M))]
  /\ fn_vars f = []
  /\ fn_body f = Ssequence (output_pre m tp) (strings_stmts m c M)
  /\ NoDup (map fst (fn_temps f))
  /\ (forall o, In o lor ->
        find_assoc (temp_name (outrel_prim (make_tables m) o)) (fn_temps f)
        = Some (ctype_of_prim (outrel_prim (make_tables m) o)))
  /\ (forall sp, topic_stamp m c = Some sp ->
        find_assoc (temp_name Puint32) (fn_temps f) = Some (ctype_of_prim Puint32)).
Proof.
  intros m p tp H Hin c M lor. exists (output_glue_function m (make_tables m) tp); repeat split.
  - apply (generate_find_def m p _ _ H). unfold build_defs; rewrite !in_app_iff.
    do 7 right; left. change (output_glue_name c, Gfun (Internal (output_glue_function m (make_tables m) tp)))
      with (output_glue_def m (make_tables m) tp). apply in_map; auto.
  - unfold output_glue_function; destruct (topic_stamp m (tp_cname tp)); reflexivity.
  - unfold output_glue_function; destruct (topic_stamp m (tp_cname tp)); reflexivity.
  - unfold output_glue_function; destruct (topic_stamp m (tp_cname tp)); reflexivity.
  - apply output_glue_body.
  - unfold output_glue_function; destruct (topic_stamp m (tp_cname tp)); apply temps_of_nodup.
  - intros o Ho. unfold output_glue_function; destruct (topic_stamp m (tp_cname tp)); apply temps_of_find;
      [apply in_or_app; right|]; apply in_map_iff; eauto.
  - intros sp E. unfold output_glue_function. unfold c in E. rewrite E. apply temps_of_find; left; auto.
Qed.

Lemma wf_cmd_vars_nodup:
  forall m, wf_facts m -> NoDup (map (fun tp => cmd_var (tp_cname tp)) (published m)).
Proof.
  intros m W. generalize (wf_names_nodup m W); intros ND.
  apply NoDup_app_inv in ND; destruct ND as (_ & ND & _). unfold local_names in ND.
  apply NoDup_app_inv in ND; destruct ND as (_ & ND & _).
  apply NoDup_app_inv in ND; tauto.
Qed.

(** [loop]: one cycle is [_ok = ros_ok(); if (_ok) ; else break;
    ros_spinOnce(); input_glue(); Controller_step();], then for each
    published topic [output_glue_c(&c_cmd); ros_publish_c(&c_cmd);], then
    [ros_rate_sleep();]. *)
Theorem generate_loop:
  forall m p, generate m = OK p ->
  exists f,
     find_def p loop_name = Some (Gfun (Internal f))
  /\ fn_return f = Tvoid /\ fn_params f = []
  /\ fn_vars f = map (fun tp => (cmd_var (tp_cname tp), Tstruct (tp_msg tp))) (published m)
  /\ NoDup (map fst (fn_vars f))
  /\ fn_temps f = [(ok_temp, tint)]
  /\ fn_body f
     = Sloop (Ssequence (Scall (Some ok_temp) (Evar ros_ok_name (Tfunction [] tint)) [])
             (Ssequence (Sifthenelse (Etempvar ok_temp tint) Sskip Sbreak)
             (Ssequence (call0 ros_spinOnce_name)
             (Ssequence (call0 input_glue_name)
             (Ssequence (call0 (step_name m))
                        (seq_of (flat_map publish_stmts (published m)
                                 ++ [call0 ros_rate_sleep_name]))))))).
Proof.
  intros m p H. exists (loop_function m); repeat split.
  - apply (generate_find_def m p _ _ H). unfold build_defs; rewrite !in_app_iff.
    do 7 right; simpl; auto.
  - simpl. rewrite map_map; simpl.
    apply wf_cmd_vars_nodup, wf_facts_intro, (generate_sound m p H).
Qed.

(** [main]. *)
Theorem generate_main:
  forall m p, generate m = OK p ->
  prog_main p = main_name
  /\ exists f,
     find_def p main_name = Some (Gfun (Internal f))
  /\ fn_return f = tint /\ fn_params f = [] /\ fn_vars f = [] /\ fn_temps f = []
  /\ fn_body f = seq_of ([call0 ros_init_name; call0 (init_name m)]
                         ++ map subscribe_stmt (subscribed m)
                         ++ map advertise_stmt (published m)
                         ++ [call0 loop_name; Sreturn (Some (Econst_int 0 tint))]).
Proof.
  intros m p H. split; [destruct (generate_inv m p H) as [_ ->]; reflexivity|].
  exists (main_function m); repeat split.
  apply (generate_find_def m p _ _ H). unfold build_defs; rewrite !in_app_iff.
  do 7 right; simpl; auto.
Qed.
