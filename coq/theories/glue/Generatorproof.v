(** * Properties of the glue-code generator *)

(** This file proves, for every node model:
    - T4: [generate] accepts exactly the well-formed models
      ([generate_complete], [generate_sound]), and [wf_check] is [wf]
      with error messages ([wf_check_wf]);
    - the facts that well-formedness gives ([wf_facts]);
    - the meaning of the leaves of a message: exactly the paths that
      resolve to a primitive ([leaves_spec]), each a well-typed C access;
    - the shape of the generated program: distinct global names, the
      function found under each generated name and its body
      ([generate_callback], [generate_input_glue], [generate_output_glue],
      [generate_loop], [generate_main]);
    - T3, the paper's Section 6 properties: relation consistency
      ([relation_consistency_input_glue], [relation_consistency_output_glue],
      Figure 15), valid assignment via type checking
      ([type_checking_input_glue_sound], [type_checking_input_glue_generated],
      Figure 16, and [generate_valid_assignments] for every generated
      function), and preservation ([loop_input_glue_then_step],
      [generate_inputs_written_only_by_input_glue],
      [generate_inputs_address_not_taken]). *)

From Coq Require Import String Ascii List ZArith Bool Lia.
From ROSGen Require Import Errors Syntax Maps NodeModel Generator.
Import ListNotations.

Local Open Scope string_scope.
Local Open Scope list_scope.
Local Open Scope error_monad_scope.

(** ** Generic lemmas *)

Lemma assertion_ok: forall b msg, assertion b msg = OK tt <-> b = true.
Proof. intros [|] msg; simpl; split; congruence. Qed.

Lemma bind_unit_ok:
  forall (a b : res unit), (do _ <- a; b) = OK tt <-> a = OK tt /\ b = OK tt.
Proof. intros [[]|e] b; simpl; intuition congruence. Qed.

Lemma check_all_ok:
  forall (A : Type) (f : A -> res unit) (g : A -> bool),
  (forall x, f x = OK tt <-> g x = true) ->
  forall l, check_all f l = OK tt <-> forallb g l = true.
Proof.
  intros A f g H; induction l as [|x l IH]; simpl.
  - tauto.
  - rewrite bind_unit_ok, andb_true_iff, H, IH; tauto.
Qed.

Lemma nodup_keys_NoDup:
  forall (A : Type) (enc : A -> list bool),
  (forall a b, enc a = enc b -> a = b) ->
  forall l, nodup_keys enc l = true <-> NoDup l.
Proof.
  intros A enc Inj l; unfold nodup_keys; rewrite <- (find_dup_None A enc Inj l).
  destruct (find_dup enc l); split; congruence.
Qed.

Lemma check_nodup_keys_ok:
  forall (A : Type) (enc : A -> list bool) show l,
  check_nodup_keys enc show l = OK tt <-> nodup_keys enc l = true.
Proof.
  intros; unfold check_nodup_keys, nodup_keys; destruct (find_dup enc l); split; congruence.
Qed.

Lemma first_dup_None:
  forall (A : Type) (eqb : A -> A -> bool),
  (forall a b, eqb a b = true <-> a = b) ->
  forall l, first_dup eqb l = None <-> NoDup l.
Proof.
  intros A eqb Heq; induction l as [|x l IH]; simpl.
  - split; auto using NoDup_nil.
  - destruct (existsb (eqb x) l) eqn:E.
    + split; [discriminate|]. intros ND; inversion ND; subst.
      apply existsb_exists in E; destruct E as (y & Hy & Exy).
      apply Heq in Exy; subst; contradiction.
    + rewrite IH, NoDup_cons_iff; split; [|tauto]. intros ND; split; auto.
      intros Hin. assert (existsb (eqb x) l = true) by
        (apply existsb_exists; exists x; split; auto; apply Heq; auto).
      congruence.
Qed.

Lemma nodupb_NoDup:
  forall (A : Type) (eqb : A -> A -> bool),
  (forall a b, eqb a b = true <-> a = b) ->
  forall l, nodupb eqb l = true <-> NoDup l.
Proof.
  intros A eqb Heq l; unfold nodupb; rewrite <- (first_dup_None A eqb Heq l).
  destruct (first_dup eqb l); split; congruence.
Qed.

Lemma check_nodup_ok:
  forall (A : Type) (eqb : A -> A -> bool) show l,
  check_nodup eqb show l = OK tt <-> nodupb eqb l = true.
Proof.
  intros; unfold check_nodup, nodupb; destruct (first_dup eqb l); split; congruence.
Qed.

Lemma NoDup_app_inv:
  forall (A : Type) (l1 l2 : list A),
  NoDup (l1 ++ l2) -> NoDup l1 /\ NoDup l2 /\ (forall x, In x l1 -> ~ In x l2).
Proof.
  induction l1 as [|a l1 IH]; simpl; intros l2 ND.
  - split; [constructor|]; split; auto.
  - inversion ND as [|? ? Hnin ND']; subst. destruct (IH _ ND') as (A1 & A2 & A3).
    split; [constructor; auto; intro; apply Hnin; apply in_or_app; auto|].
    split; auto. intros x [<-|Hx] Hx2; [apply Hnin; apply in_or_app; auto|eapply A3; eauto].
Qed.

(** Two names at different places of a list without duplicates differ. *)
Lemma NoDup_app_neq:
  forall (A : Type) (l1 l2 : list A) x y,
  NoDup (l1 ++ l2) -> In x l1 -> In y l2 -> x <> y.
Proof.
  intros A l1 l2 x y ND Hx Hy <-. apply NoDup_app_inv in ND. destruct ND as (_ & _ & D).
  eapply D; eauto.
Qed.

Lemma find_assoc_In:
  forall (A : Type) x (l : list (ident * A)) v, find_assoc x l = Some v -> In (x, v) l.
Proof.
  induction l as [|[y w] l IH]; simpl; intros v H; [discriminate|].
  destruct (string_dec x y); [inversion H; subst; auto | auto].
Qed.

Lemma In_find_assoc:
  forall (A : Type) x (l : list (ident * A)) v,
  NoDup (map fst l) -> In (x, v) l -> find_assoc x l = Some v.
Proof.
  induction l as [|[y w] l IH]; simpl; intros v ND H; [contradiction|].
  inversion ND as [|? ? Hnin ND']; subst.
  destruct (string_dec x y) as [<-|n].
  - destruct H as [E|H]; [congruence|].
    elim Hnin. change x with (fst (x, v)). apply in_map; auto.
  - destruct H as [E|H]; [congruence|auto].
Qed.

Lemma find_assoc_None:
  forall (A : Type) x (l : list (ident * A)), find_assoc x l = None -> ~ In x (map fst l).
Proof.
  induction l as [|[y w] l IH]; simpl; intros H; [auto|].
  destruct (string_dec x y); [discriminate|]. intros [E|E]; [congruence|tauto].
Qed.

Lemma find_assoc_filter:
  forall (A : Type) (P : ident * A -> bool) x l v,
  find_assoc x l = Some v -> P (x, v) = true -> find_assoc x (filter P l) = Some v.
Proof.
  induction l as [|[y w] l IH]; simpl; intros v H HP; [discriminate|].
  destruct (string_dec x y) as [<-|n].
  - inversion H; subst. rewrite HP; simpl. destruct (string_dec x x); congruence.
  - destruct (P (y, w)); simpl; auto.
    destruct (string_dec x y); [congruence|auto].
Qed.

Lemma find_assoc_app_left:
  forall (A : Type) x (l1 l2 : list (ident * A)) v,
  find_assoc x l1 = Some v -> find_assoc x (l1 ++ l2) = Some v.
Proof.
  induction l1 as [|[y w] l1 IH]; simpl; intros l2 v H; [discriminate|].
  destruct (string_dec x y); auto.
Qed.

Lemma find_assoc_app_right:
  forall (A : Type) x (l1 l2 : list (ident * A)),
  ~ In x (map fst l1) -> find_assoc x (l1 ++ l2) = find_assoc x l2.
Proof.
  induction l1 as [|[y w] l1 IH]; simpl; intros l2 H; auto.
  destruct (string_dec x y); [subst; tauto|]. apply IH; tauto.
Qed.

Lemma ident_eqb_sym: forall a b, ident_eqb a b = ident_eqb b a.
Proof.
  intros a b; destruct (ident_eqb a b) eqn:E; destruct (ident_eqb b a) eqn:F; auto.
  - apply ident_eqb_true in E; subst; rewrite ident_eqb_refl in F; discriminate.
  - apply ident_eqb_true in F; subst; rewrite ident_eqb_refl in E; discriminate.
Qed.

Lemma enc_pstep_prefix_free: prefix_free enc_pstep.
Proof.
  intros [f|i] [g|j] r1 r2; simpl; intros E; inversion E as [E'].
  - destruct (enc_string_prefix_free f g r1 r2 E') as [-> ->]; auto.
  - destruct (enc_Z_prefix_free i j r1 r2 E') as [-> ->]; auto.
Qed.

Lemma enc_string_inj: forall a b, enc_string a = enc_string b -> a = b.
Proof. apply prefix_free_inj, enc_string_prefix_free. Qed.

Lemma enc_target_inj: forall a b, enc_target a = enc_target b -> a = b.
Proof.
  apply prefix_free_inj, enc_pair_prefix_free;
    [apply enc_string_prefix_free|apply enc_list_prefix_free, enc_pstep_prefix_free].
Qed.

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
  destruct (tget (enc_string (ir_input ir)) (tb_inputs tb)) as [q|]; [|intuition discriminate].
  destruct (resolve_prim (nm_msgs m) (FTmsg (tp_msg tp)) (ir_path ir)) as [q'|];
    [rewrite assertion_ok|]; intuition discriminate.
Qed.

Lemma outrel_check_ok:
  forall m tb o, outrel_check m tb o = OK tt <-> outrel_ok m tb o = true.
Proof.
  intros; unfold outrel_check, outrel_ok.
  destruct (tget (enc_string (or_output o)) (tb_outputs tb)) as [q|]; [|split; discriminate].
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
Corollary generate_refuses: forall m, wf m = false -> exists msg, generate m = Error msg.
Proof.
  intros m H; unfold generate. destruct (wf_check m) as [[]|e] eqn:E.
  - apply wf_check_wf in E; congruence.
  - exists e; reflexivity.
Qed.

(** ** What well-formedness gives *)

Record wf_facts (m : node_model) : Prop := {
  wf_period: (0 < nm_period_ms m)%Z;
  wf_names_valid: forall x, In x (c_names m) -> valid_ident x = true;
  wf_names_nodup: NoDup (global_names m ++ local_names m);
  wf_structs_nodup: NoDup (struct_names m);
  wf_msgs: msgs_ok [] (nm_msgs m) = true;
  wf_inputs_nonempty: nm_inputs m <> [];
  wf_inputs_nodup: NoDup (map fst (nm_inputs m));
  wf_outputs_nonempty: nm_outputs m <> [];
  wf_outputs_nodup: NoDup (map fst (nm_outputs m));
  wf_cnames_nodup: NoDup (map tp_cname (nm_topics m));
  wf_rosnames_nodup: NoDup (map tp_name (nm_topics m));
  wf_topics: forall tp, In tp (nm_topics m) -> topic_ok (nm_msgs m) tp = true;
  wf_inrels: forall ir, In ir (nm_inrels m) -> inrel_ok m (make_tables m) ir = true;
  wf_inrel_inputs_nodup: NoDup (map ir_input (nm_inrels m));
  wf_inputs_fed: forall x q, In (x, q) (nm_inputs m) -> In x (map ir_input (nm_inrels m));
  wf_outrels: forall o, In o (nm_outrels m) -> outrel_ok m (make_tables m) o = true;
  wf_out_targets: NoDup (map (fun o => (or_topic o, or_path o)) (nm_outrels m))
}.

Lemma null_false: forall (A : Type) (l : list A), negb (null l) = true -> l <> [].
Proof. intros A [|x l]; simpl; congruence. Qed.

Lemma wf_facts_intro: forall m, wf m = true -> wf_facts m.
Proof.
  intros m H; unfold wf in H; cbv zeta in H. rewrite !andb_true_iff in H.
  repeat match type of H with _ /\ _ => let H1 := fresh "H" in destruct H as [H H1] end.
  rewrite ?(nodup_keys_NoDup _ _ enc_string_inj) in *.
  rewrite ?(nodup_keys_NoDup _ _ enc_target_inj) in *.
  rewrite ?forallb_forall in *.
  constructor; auto using null_false.
  - apply Z.ltb_lt; auto.
  - intros x q Hin.
    match goal with Hf : forall xq, In xq (nm_inputs m) -> tmem _ _ _ = true |- _ =>
      generalize (Hf (x, q) Hin) end.
    unfold fed_inputs; rewrite (tmem_of_list _ _ enc_string_inj); auto.
Qed.

(** ** The lookup tables *)

Lemma tmap_of_list_find_assoc:
  forall (A : Type) (l : list (ident * A)) x,
  tget (enc_string x) (tmap_of_list enc_string l) = find_assoc x l.
Proof.
  induction l as [|[y v] l IH]; intros x; simpl; auto using tget_leaf.
  destruct (string_dec x y) as [<-|n]; [apply tget_tset_same|].
  rewrite tget_tset_other; auto. intros E; apply n, enc_string_inj; auto.
Qed.

Lemma tables_topics:
  forall m c, lookup_topic (make_tables m) c = find_topic (nm_topics m) c.
Proof.
  intros m c; unfold lookup_topic, make_tables, find_topic; simpl.
  induction (nm_topics m) as [|tp l IH]; simpl; auto using tget_leaf.
  destruct (ident_eqb (tp_cname tp) c) eqn:E.
  - apply ident_eqb_true in E; subst; apply tget_tset_same.
  - rewrite tget_tset_other; auto. intros E'; apply enc_string_inj in E'.
    apply ident_eqb_false in E; auto.
Qed.

Lemma tables_inputs:
  forall m x, tget (enc_string x) (tb_inputs (make_tables m)) = find_assoc x (nm_inputs m).
Proof. intros; apply tmap_of_list_find_assoc. Qed.

Lemma tables_outputs:
  forall m x, tget (enc_string x) (tb_outputs (make_tables m)) = find_assoc x (nm_outputs m).
Proof. intros; apply tmap_of_list_find_assoc. Qed.

Lemma tables_outrels:
  forall m c, topic_outrels (make_tables m) c = filter (fun o => ident_eqb (or_topic o) c) (nm_outrels m).
Proof.
  intros m c; unfold topic_outrels, make_tables; simpl.
  induction (nm_outrels m) as [|o l IH]; simpl;
    [unfold tget_default; rewrite tget_leaf; reflexivity|].
  unfold tget_default at 1.
  destruct (ident_eqb (or_topic o) c) eqn:E.
  - apply ident_eqb_true in E; subst. rewrite tget_tset_same. f_equal; auto.
  - rewrite tget_tset_other; auto. intros E'; apply enc_string_inj in E'.
    apply ident_eqb_false in E; auto.
Qed.

Lemma In_topic_outrels:
  forall m c o, In o (topic_outrels (make_tables m) c) <-> In o (nm_outrels m) /\ or_topic o = c.
Proof.
  intros; rewrite tables_outrels, filter_In, ident_eqb_true; tauto.
Qed.

Lemma input_prim_tables:
  forall m x q, find_assoc x (nm_inputs m) = Some q -> input_prim (make_tables m) x = q.
Proof. intros m x q H; unfold input_prim; rewrite tables_inputs, H; auto. Qed.

Lemma output_prim_tables:
  forall m x q, find_assoc x (nm_outputs m) = Some q -> output_prim (make_tables m) x = q.
Proof. intros m x q H; unfold output_prim; rewrite tables_outputs, H; auto. Qed.

Lemma topic_msg_tables:
  forall m c tp, find_topic (nm_topics m) c = Some tp -> topic_msg (make_tables m) c = tp_msg tp.
Proof. intros m c tp H; unfold topic_msg; rewrite tables_topics, H; auto. Qed.

(** Topics by C name. *)
Lemma find_topic_In:
  forall tps c tp, find_topic tps c = Some tp -> In tp tps /\ tp_cname tp = c.
Proof.
  unfold find_topic; intros tps c tp H. apply find_some in H.
  destruct H as [H1 H2]; apply ident_eqb_true in H2; auto.
Qed.

Lemma In_find_topic:
  forall tps tp, NoDup (map tp_cname tps) -> In tp tps -> find_topic tps (tp_cname tp) = Some tp.
Proof.
  unfold find_topic; induction tps as [|tp0 tps IH]; simpl; intros tp ND H; [contradiction|].
  inversion ND as [|? ? Hnin ND']; subst.
  destruct H as [<-|H]; [rewrite ident_eqb_refl; auto|].
  destruct (ident_eqb (tp_cname tp0) (tp_cname tp)) eqn:E; auto.
  apply ident_eqb_true in E. elim Hnin; rewrite E; apply in_map; auto.
Qed.

Lemma resolve_prim_inv:
  forall msgs t p q, resolve_prim msgs t p = Some q <-> resolve msgs t p = Some (FTprim q).
Proof.
  unfold resolve_prim; intros. destruct (resolve msgs t p) as [[]|]; split; congruence.
Qed.

(** An input relation reads a leaf of a subscribed topic's message of the
    input's primitive type: the paper's [type_checking_input_glue] on model
    types. *)
Lemma wf_inrel:
  forall m ir, wf_facts m -> In ir (nm_inrels m) ->
  exists tp q,
     find_topic (nm_topics m) (ir_topic ir) = Some tp /\ is_subscribed tp = true
  /\ find_assoc (ir_input ir) (nm_inputs m) = Some q
  /\ resolve (nm_msgs m) (FTmsg (tp_msg tp)) (ir_path ir) = Some (FTprim q).
Proof.
  intros m ir W Hin. generalize (wf_inrels m W ir Hin); unfold inrel_ok.
  rewrite tables_topics, tables_inputs.
  destruct (find_topic (nm_topics m) (ir_topic ir)) as [tp|]; [|discriminate].
  destruct (find_assoc (ir_input ir) (nm_inputs m)) as [q|]; [|rewrite andb_false_r; discriminate].
  destruct (resolve_prim (nm_msgs m) (FTmsg (tp_msg tp)) (ir_path ir)) as [q'|] eqn:R;
    [|rewrite andb_false_r; discriminate].
  rewrite andb_true_iff, prim_eqb_true; intros [S <-].
  exists tp, q'; repeat split; auto. apply resolve_prim_inv; auto.
Qed.

Lemma wf_outrel:
  forall m o, wf_facts m -> In o (nm_outrels m) ->
  exists tp q,
     find_topic (nm_topics m) (or_topic o) = Some tp /\ is_published tp = true
  /\ find_assoc (or_output o) (nm_outputs m) = Some q
  /\ resolve (nm_msgs m) (FTmsg (tp_msg tp)) (or_path o) = Some (FTprim q).
Proof.
  intros m o W Hin. generalize (wf_outrels m W o Hin); unfold outrel_ok.
  rewrite tables_topics, tables_outputs.
  destruct (find_assoc (or_output o) (nm_outputs m)) as [q|]; [|discriminate].
  destruct (find_topic (nm_topics m) (or_topic o)) as [tp|]; [|discriminate].
  destruct (resolve_prim (nm_msgs m) (FTmsg (tp_msg tp)) (or_path o)) as [q'|] eqn:R;
    [|rewrite andb_false_r; discriminate].
  rewrite andb_true_iff, prim_eqb_true; intros [S <-].
  exists tp, q'; repeat split; auto. apply resolve_prim_inv; auto.
Qed.

(** The number of input relations that feed controller input [x]. *)
Definition feeds (m : node_model) (x : ident) : nat :=
  length (filter (fun ir => ident_eqb (ir_input ir) x) (nm_inrels m)).

Lemma filter_nodup_single:
  forall (l : list inrel) x,
  NoDup (map ir_input l) -> In x (map ir_input l) ->
  exists ir, filter (fun ir => ident_eqb (ir_input ir) x) l = [ir].
Proof.
  induction l as [|ir l IH]; simpl; intros x ND H; [contradiction|].
  inversion ND as [|? ? Hn ND']; subst.
  destruct (ident_eqb (ir_input ir) x) eqn:E.
  - apply ident_eqb_true in E; subst. exists ir. f_equal.
    destruct (filter (fun ir' => ident_eqb (ir_input ir') (ir_input ir)) l) as [|ir' l'] eqn:F; auto.
    assert (In ir' (filter (fun ir' => ident_eqb (ir_input ir') (ir_input ir)) l)) by (rewrite F; simpl; auto).
    apply filter_In in H0; destruct H0 as [H0 E']. apply ident_eqb_true in E'.
    elim Hn; rewrite <- E'; apply in_map; auto.
  - destruct H as [H|H]; [apply ident_eqb_false in E; contradiction|]. apply IH; auto.
Qed.

(** Every controller input is fed by exactly one input relation. *)
Lemma wf_input_fed_once:
  forall m x q, wf_facts m -> In (x, q) (nm_inputs m) ->
  exists ir, filter (fun ir => ident_eqb (ir_input ir) x) (nm_inrels m) = [ir].
Proof.
  intros m x q W H. apply filter_nodup_single.
  - apply wf_inrel_inputs_nodup; auto.
  - apply (wf_inputs_fed m W x q H).
Qed.

Lemma wf_feeds: forall m, wf_facts m -> forall x q, In (x, q) (nm_inputs m) -> feeds m x = 1%nat.
Proof.
  intros m W x q H. unfold feeds. destruct (wf_input_fed_once m x q W H) as (ir & ->); auto.
Qed.

(** ** Messages: scopes, resolution and leaves *)

Definition md_names (l : list msgdef) : list ident := map md_name l.

(** A scope (message definitions, latest first) is well formed when each
    definition has distinct field names and refers only to definitions after
    it, and names are distinct. *)
Inductive scope_ok : list msgdef -> Prop :=
  | scope_ok_nil: scope_ok []
  | scope_ok_cons: forall md rest,
      ~ In (md_name md) (md_names rest) ->
      NoDup (map fst (md_fields md)) ->
      (forall f t, In (f, t) (md_fields md) -> ftype_ok (md_names rest) t = true) ->
      scope_ok rest ->
      scope_ok (md :: rest).

Lemma ftype_ok_incl:
  forall s1 s2 t, incl s1 s2 -> ftype_ok s1 t = true -> ftype_ok s2 t = true.
Proof.
  induction t as [q|id|t IH n]; simpl; intros Hincl H; auto.
  - apply existsb_exists in H; destruct H as (y & Hy & E).
    apply existsb_exists; exists y; split; auto.
  - rewrite !andb_true_iff in *; intuition.
Qed.

Lemma ftype_ok_msg: forall s id, ftype_ok s (FTmsg id) = true <-> In id s.
Proof.
  intros s id; simpl; rewrite existsb_exists; split.
  - intros (y & Hy & E); apply ident_eqb_true in E; subst; auto.
  - intros H; exists id; split; auto; apply ident_eqb_refl.
Qed.

Lemma scope_ok_fields:
  forall scope, scope_ok scope ->
  forall md f t, In md scope -> In (f, t) (md_fields md) -> ftype_ok (md_names scope) t = true.
Proof.
  induction 1 as [|md0 rest Hn ND Hf Hs IH]; simpl; intros md f t Hmd Hft; [contradiction|].
  apply ftype_ok_incl with (md_names rest); [intros x Hx; simpl; auto|].
  destruct Hmd as [<-|Hmd]; eauto.
Qed.

Lemma find_msg_In:
  forall l id md, find_msg l id = Some md -> In md l /\ md_name md = id.
Proof.
  unfold find_msg; intros l id md H; apply find_some in H.
  destruct H as [H E]; apply ident_eqb_true in E; auto.
Qed.

Lemma find_msg_None: forall l id, find_msg l id = None -> ~ In id (md_names l).
Proof.
  unfold find_msg, md_names; intros l id H Hin. apply in_map_iff in Hin.
  destruct Hin as (md & E & Hmd). apply (find_none _ _ H) in Hmd.
  rewrite E, ident_eqb_refl in Hmd; discriminate.
Qed.

Lemma find_msg_unique:
  forall l id md, NoDup (md_names l) -> In md l -> md_name md = id -> find_msg l id = Some md.
Proof.
  unfold find_msg, md_names; induction l as [|md0 l IH]; simpl; intros id md ND Hin E;
    [contradiction|].
  inversion ND as [|? ? Hnin ND']; subst.
  destruct Hin as [<-|Hin]; [rewrite ident_eqb_refl; auto|].
  destruct (ident_eqb (md_name md0) (md_name md)) eqn:F; auto.
  apply ident_eqb_true in F. elim Hnin; rewrite F; apply in_map; auto.
Qed.

Lemma find_msg_rev:
  forall l id, NoDup (md_names l) -> find_msg (rev l) id = find_msg l id.
Proof.
  intros l id ND.
  assert (NDr: NoDup (md_names (rev l))) by (unfold md_names; rewrite map_rev; apply NoDup_rev; auto).
  destruct (find_msg l id) as [md|] eqn:E.
  - apply find_msg_In in E; destruct E as [Hin E].
    apply find_msg_unique; auto. apply -> in_rev; auto.
  - destruct (find_msg (rev l) id) as [md|] eqn:F; auto.
    apply find_msg_In in F; destruct F as [Hin F]. apply find_msg_None in E.
    elim E; unfold md_names; rewrite <- F; apply in_map.
    apply <- in_rev; auto.
Qed.

Lemma resolve_find_ext:
  forall l1 l2, (forall id, find_msg l1 id = find_msg l2 id) ->
  forall p t, resolve l1 t p = resolve l2 t p.
Proof.
  intros l1 l2 H; induction p as [|[f|i] p IH]; intros t; simpl; auto.
  - destruct t as [q|id|t' n]; auto. rewrite H. destruct (find_msg l2 id) as [md|]; auto.
    destruct (find_assoc f (md_fields md)); auto.
  - destruct t; auto. destruct ((0 <=? i)%Z && (i <? n)%Z); auto.
Qed.

Lemma resolve_rev:
  forall l t p, NoDup (md_names l) -> resolve (rev l) t p = resolve l t p.
Proof. intros; apply resolve_find_ext; intros; apply find_msg_rev; auto. Qed.

(** Adding a definition in front of a scope does not change the resolution
    of a field type that refers only to the scope. *)
Lemma resolve_cons:
  forall md0 rest, scope_ok (md0 :: rest) ->
  forall p t, ftype_ok (md_names rest) t = true ->
  resolve (md0 :: rest) t p = resolve rest t p.
Proof.
  intros md0 rest Hs. inversion Hs as [|? ? Hn ND Hf Hrest]; subst.
  induction p as [|[f|i] p IH]; intros t Ht; simpl; auto.
  - destruct t as [q|id|t n]; auto.
    apply ftype_ok_msg in Ht.
    unfold find_msg at 1; simpl.
    destruct (ident_eqb (md_name md0) id) eqn:E.
    { apply ident_eqb_true in E; subst; contradiction. }
    fold (find_msg rest id).
    destruct (find_msg rest id) as [md|] eqn:F; auto.
    destruct (find_assoc f (md_fields md)) as [t'|] eqn:G; auto.
    apply IH. apply find_msg_In in F. apply find_assoc_In in G.
    eapply scope_ok_fields; eauto; tauto.
  - destruct t as [q|id|t n]; auto. simpl in Ht.
    destruct ((0 <=? i)%Z && (i <? n)%Z); auto. apply IH. rewrite !andb_true_iff in Ht; tauto.
Qed.

Lemma resolve_cons_msg:
  forall md0 rest id p, scope_ok (md0 :: rest) -> md_name md0 <> id ->
  resolve (md0 :: rest) (FTmsg id) p = resolve rest (FTmsg id) p.
Proof.
  intros md0 rest id p Hs Hne.
  destruct (in_dec string_dec id (md_names rest)) as [Hin|Hnin].
  - apply resolve_cons; auto. apply ftype_ok_msg; auto.
  - destruct p as [|[f|i] p]; simpl; auto.
    unfold find_msg; simpl. apply ident_eqb_false in Hne; rewrite Hne. fold (find_msg rest id).
    destruct (find_msg rest id) as [md|] eqn:F; auto.
    apply find_msg_In in F; destruct F as [F1 F2]; subst.
    elim Hnin; apply in_map; auto.
Qed.

Lemma In_prefix_leaves:
  forall s l p q, In (p, q) (prefix_leaves s l) <-> exists p', p = s :: p' /\ In (p', q) l.
Proof.
  unfold prefix_leaves; intros s l p q; rewrite in_map_iff; split.
  - intros ([p' q'] & E & H); simpl in E; inversion E; subst; eauto.
  - intros (p' & -> & H); exists (p', q); auto.
Qed.

Lemma In_zrange: forall n i, In i (zrange n) <-> (0 <= i < n)%Z.
Proof.
  unfold zrange; intros n i; rewrite in_map_iff; split.
  - intros (k & <- & Hk). apply in_seq in Hk. lia.
  - intros Hi. exists (Z.to_nat i); split; [lia|]. apply in_seq; lia.
Qed.

(** The leaves of a field type are the paths that resolve to a primitive. *)
Lemma ftype_leaves_spec:
  forall scope ml,
  (forall id p q, In (p, q) (ml id) <-> resolve scope (FTmsg id) p = Some (FTprim q)) ->
  forall t p q, In (p, q) (ftype_leaves ml t) <-> resolve scope t p = Some (FTprim q).
Proof.
  intros scope ml Hml; induction t as [q0|id|t IH n]; intros p q; simpl.
  - destruct p as [|[f|i] p]; simpl; split; try (intros [E|[]]; congruence); try discriminate.
    intros E; inversion E; subst; left; auto.
  - apply Hml.
  - rewrite in_flat_map. split.
    + intros (i & Hi & H). apply In_zrange in Hi. apply In_prefix_leaves in H.
      destruct H as (p' & -> & H). simpl.
      replace ((0 <=? i)%Z && (i <? n)%Z) with true
      by (symmetry; rewrite andb_true_iff, Z.leb_le, Z.ltb_lt; lia).
      apply IH; auto.
    + destruct p as [|[f|i] p]; simpl; try congruence.
      destruct ((0 <=? i)%Z && (i <? n)%Z) eqn:E; [|congruence].
      intros H; exists i; split; [apply In_zrange; rewrite andb_true_iff, Z.leb_le, Z.ltb_lt in E; lia|].
      apply In_prefix_leaves; exists p; split; auto. apply IH; auto.
Qed.

Lemma scope_leaves_spec:
  forall scope, scope_ok scope ->
  forall id p q, In (p, q) (scope_leaves scope id) <-> resolve scope (FTmsg id) p = Some (FTprim q).
Proof.
  induction 1 as [|md rest Hn ND Hf Hs IH]; intros id p q; simpl.
  - destruct p as [|[f|i] p]; simpl; split; intuition congruence.
  - destruct (ident_eqb (md_name md) id) eqn:E.
    + apply ident_eqb_true in E; subst id.
      unfold fields_leaves; rewrite in_flat_map.
      destruct p as [|[f|i] p]; simpl.
      * split; [intros ([f t] & _ & H); apply In_prefix_leaves in H;
                destruct H as (p' & E & _); discriminate | congruence].
      * unfold find_msg; simpl; rewrite ident_eqb_refl. split.
        -- intros ([f' t] & Hft & H). apply In_prefix_leaves in H.
           destruct H as (p' & E & H); inversion E; subst; simpl in *.
           rewrite (In_find_assoc _ _ _ _ ND Hft).
           rewrite resolve_cons by (eauto || (econstructor; eauto)).
           apply (ftype_leaves_spec rest (scope_leaves rest) IH); auto.
        -- destruct (find_assoc f (md_fields md)) as [t|] eqn:F; [|congruence].
           intros H. apply find_assoc_In in F. exists (f, t); split; auto.
           apply In_prefix_leaves; exists p; split; auto. simpl.
           apply (ftype_leaves_spec rest (scope_leaves rest) IH).
           rewrite resolve_cons in H by (eauto || (econstructor; eauto)); auto.
      * split; [intros ([f t] & _ & H); apply In_prefix_leaves in H;
                destruct H as (p' & E & _); discriminate | congruence].
    + apply ident_eqb_false in E.
      rewrite resolve_cons_msg by (auto; econstructor; eauto). apply IH.
Qed.

Lemma msgs_ok_scope:
  forall msgs scope, scope_ok scope ->
  msgs_ok (md_names scope) msgs = true ->
  NoDup (md_names (rev msgs ++ scope)) ->
  scope_ok (rev msgs ++ scope).
Proof.
  induction msgs as [|md msgs IH]; simpl; intros scope Hs Hok ND; auto.
  rewrite andb_true_iff in Hok; destruct Hok as [Hmd Hok].
  rewrite <- app_assoc; simpl. rewrite <- app_assoc in ND; simpl in ND.
  apply IH; auto.
  unfold md_names in ND; rewrite map_app in ND; simpl in ND.
  apply NoDup_app_inv in ND; destruct ND as (_ & ND & _).
  inversion ND as [|? ? Hnin ND']; subst.
  unfold msgdef_ok in Hmd; rewrite !andb_true_iff in Hmd.
  destruct Hmd as ((Hne & Hnd) & Hft).
  constructor; auto.
  - apply (nodupb_NoDup _ _ ident_eqb_true); auto.
  - intros f t Hin. rewrite forallb_forall in Hft. apply (Hft (f, t) Hin).
Qed.

(** The message definitions of a well-formed model form a well-formed
    scope, latest first. *)
Lemma wf_scope_ok: forall m, wf_facts m -> scope_ok (rev (nm_msgs m)).
Proof.
  intros m W. rewrite <- app_nil_r.
  apply msgs_ok_scope; [constructor|apply wf_msgs; auto|].
  rewrite app_nil_r. unfold md_names; rewrite map_rev. apply NoDup_rev.
  generalize (wf_structs_nodup m W); unfold struct_names; intros ND.
  apply NoDup_app_inv in ND; tauto.
Qed.

Lemma wf_msg_names_nodup: forall m, wf_facts m -> NoDup (md_names (nm_msgs m)).
Proof.
  intros m W. generalize (wf_structs_nodup m W); unfold struct_names; intros ND.
  apply NoDup_app_inv in ND; tauto.
Qed.

(** The leaves of a message are exactly its paths to a primitive (every
    field, every array element), with their primitive types. *)
Theorem leaves_spec:
  forall m id p q, wf_facts m ->
  In (p, q) (leaves (nm_msgs m) id) <-> resolve (nm_msgs m) (FTmsg id) p = Some (FTprim q).
Proof.
  intros m id p q W. unfold leaves.
  rewrite scope_leaves_spec by (apply wf_scope_ok; auto).
  rewrite resolve_rev by (apply wf_msg_names_nodup; auto). tauto.
Qed.

(** ** C types of paths *)

Lemma find_composite_msgs:
  forall msgs extra id md, find_msg msgs id = Some md ->
  find_composite id (map composite_of_msgdef msgs ++ extra) = Some (composite_of_msgdef md).
Proof.
  unfold find_msg, find_composite; induction msgs as [|md0 msgs IH]; simpl; intros extra id md H;
    [discriminate|].
  destruct (string_dec (md_name md0) id) as [E|E].
  - rewrite (proj2 (ident_eqb_true _ _) E) in H; inversion H; auto.
  - rewrite (proj2 (ident_eqb_false _ _) E) in H; auto.
Qed.

Lemma find_composite_skip_msgs:
  forall msgs extra id, ~ In id (md_names msgs) ->
  find_composite id (map composite_of_msgdef msgs ++ extra) = find_composite id extra.
Proof.
  unfold find_composite; induction msgs as [|md0 msgs IH]; simpl; intros extra id H; auto.
  destruct (string_dec (md_name md0) id) as [E|E]; [tauto|]. apply IH; tauto.
Qed.

Lemma find_assoc_map_ctype:
  forall f (fs : list (ident * ftype)),
  find_assoc f (map (fun ft => (fst ft, ctype_of_ftype (snd ft))) fs)
  = option_map ctype_of_ftype (find_assoc f fs).
Proof.
  induction fs as [|[g t] fs IH]; simpl; auto. destruct (string_dec f g); auto.
Qed.

(** A model path that resolves has the corresponding C type. *)
Lemma resolve_type_of_path:
  forall msgs extra p t t', resolve msgs t p = Some t' ->
  type_of_path (map composite_of_msgdef msgs ++ extra) (ctype_of_ftype t) p = Some (ctype_of_ftype t').
Proof.
  induction p as [|[f|i] p IH]; simpl; intros t t' H.
  - inversion H; auto.
  - destruct t as [q|id|t n]; try discriminate.
    destruct (find_msg msgs id) as [md|] eqn:F; [|discriminate]. simpl.
    unfold field_type; rewrite (find_composite_msgs _ _ _ _ F).
    unfold composite_of_msgdef; simpl; rewrite find_assoc_map_ctype.
    destruct (find_assoc f (md_fields md)) as [t1|]; [simpl; auto|discriminate].
  - destruct t as [q|id|t n]; try discriminate; simpl.
    destruct ((0 <=? i)%Z && (i <? n)%Z); auto; discriminate.
Qed.

Lemma typeof_path_expr:
  forall ce p e t, type_of_path ce (typeof e) p = Some t -> typeof (path_expr ce e p) = t.
Proof.
  induction p as [|[f|i] p IH]; simpl; intros e t H.
  - congruence.
  - destruct (typeof e) as [| | | | | | |id] eqn:T; try discriminate.
    apply IH; simpl.
    destruct (field_type ce id f); [auto|discriminate].
  - destruct (typeof e) as [| | | | |t0 n| |] eqn:T; try discriminate.
    destruct ((0 <=? i)%Z && (i <? n)%Z); [|discriminate].
    apply IH; simpl; auto.
Qed.

(** The type of [e.p] depends only on the type of [e]. *)
Lemma typeof_path_expr_indep:
  forall ce p e1 e2, typeof e1 = typeof e2 -> typeof (path_expr ce e1 p) = typeof (path_expr ce e2 p).
Proof.
  induction p as [|s p IH]; simpl; intros e1 e2 H; auto.
  apply IH. destruct s; simpl; rewrite H; auto.
Qed.

(** ** Places *)

(** The place an expression designates: a variable or the target of a
    pointer temporary, and a path from there.  Used to state what the
    generated code reads and writes. *)
Inductive place_root : Type :=
  | Rvar (x : ident)       (**r a global or addressable local variable [x] *)
  | Rderef (x : ident).    (**r [*x] for a temporary (parameter) [x] *)

Fixpoint expr_place (e : expr) : option (place_root * path) :=
  match e with
  | Evar x _ => Some (Rvar x, [])
  | Ederef (Etempvar x _) _ => Some (Rderef x, [])
  | Efield e' f _ =>
      match expr_place e' with Some (r, p) => Some (r, p ++ [PField f]) | None => None end
  | Eindex e' (Econst_int i _) _ =>
      match expr_place e' with Some (r, p) => Some (r, p ++ [PIndex i]) | None => None end
  | _ => None
  end.

Lemma expr_place_path_expr:
  forall ce p e r q, expr_place e = Some (r, q) -> expr_place (path_expr ce e p) = Some (r, q ++ p).
Proof.
  induction p as [|[f|i] p IH]; simpl; intros e r q H.
  - rewrite app_nil_r; auto.
  - rewrite (IH _ r (q ++ [PField f])); [rewrite <- app_assoc; auto|simpl; rewrite H; auto].
  - rewrite (IH _ r (q ++ [PIndex i])); [rewrite <- app_assoc; auto|simpl; rewrite H; auto].
Qed.

(** Well-typed places: every field exists in its struct, every index is a
    constant in range. *)
Inductive wt_place (ce : list composite_definition) : expr -> Prop :=
  | wt_Evar: forall x t,
      wt_place ce (Evar x t)
  | wt_Ederef: forall x t,
      wt_place ce (Ederef (Etempvar x (tptr t)) t)
  | wt_Efield: forall e f id t,
      wt_place ce e -> typeof e = Tstruct id -> field_type ce id f = Some t ->
      wt_place ce (Efield e f t)
  | wt_Eindex: forall e i t n,
      wt_place ce e -> typeof e = Tarray t n -> (0 <= i < n)%Z ->
      wt_place ce (Eindex e (Econst_int i tint) t).

Lemma path_expr_wt:
  forall ce p e t, wt_place ce e -> type_of_path ce (typeof e) p = Some t ->
  wt_place ce (path_expr ce e p).
Proof.
  induction p as [|[f|i] p IH]; simpl; intros e t W H; auto.
  - destruct (typeof e) as [| | | | | | |id] eqn:T; try discriminate.
    destruct (field_type ce id f) as [t1|] eqn:F; [|discriminate].
    apply IH with t; simpl; try rewrite T; simpl; try rewrite F; auto.
    econstructor; eauto.
  - destruct (typeof e) as [| | | | |t0 n| |] eqn:T; try discriminate.
    destruct ((0 <=? i)%Z && (i <? n)%Z) eqn:E; [|discriminate].
    rewrite andb_true_iff, Z.leb_le, Z.ltb_lt in E.
    apply IH with t; simpl; try rewrite T; auto. econstructor; eauto.
Qed.

(** ** Typing of the generated accesses *)

Section TYPING.

Variable m : node_model.
Hypothesis W : wf_facts m.


Lemma leaf_type_of_path:
  forall M p q, In (p, q) (leaves (nm_msgs m) M) ->
  type_of_path (composites m) (Tstruct M) p = Some (ctype_of_prim q).
Proof.
  intros M p q H. apply leaves_spec in H; auto.
  apply (resolve_type_of_path _ _ _ (FTmsg M) (FTprim q) H).
Qed.

Lemma resolve_prim_type_of_path:
  forall M p q, resolve (nm_msgs m) (FTmsg M) p = Some (FTprim q) ->
  type_of_path (composites m) (Tstruct M) p = Some (ctype_of_prim q).
Proof.
  intros M p q H. apply (resolve_type_of_path _ _ _ (FTmsg M) (FTprim q) H).
Qed.

(** A path to a scalar leaf of [M], from a place of type [struct M], is a
    well-typed place of the leaf's C type. *)
Lemma leaf_path_expr_typed:
  forall M p q e, resolve (nm_msgs m) (FTmsg M) p = Some (FTprim q) ->
  typeof e = Tstruct M -> wt_place (composites m) e ->
  typeof (path_expr (composites m) e p) = ctype_of_prim q /\ wt_place (composites m) (path_expr (composites m) e p).
Proof.
  intros M p q e R T WT. apply resolve_prim_type_of_path in R. rewrite <- T in R.
  split; [apply typeof_path_expr; auto|eapply path_expr_wt; eauto].
Qed.

Lemma in_struct_not_msg: ~ In (nm_in_struct m) (md_names (nm_msgs m)).
Proof.
  generalize (wf_structs_nodup m W); unfold struct_names; intros ND.
  apply NoDup_app_inv in ND; destruct ND as (_ & _ & D). intros H; eapply D; eauto; simpl; auto.
Qed.

Lemma out_struct_not_msg: ~ In (nm_out_struct m) (md_names (nm_msgs m)).
Proof.
  generalize (wf_structs_nodup m W); unfold struct_names; intros ND.
  apply NoDup_app_inv in ND; destruct ND as (_ & _ & D). intros H; eapply D; eauto; simpl; auto.
Qed.

Lemma in_out_structs_differ: nm_in_struct m <> nm_out_struct m.
Proof.
  generalize (wf_structs_nodup m W); unfold struct_names; intros ND.
  apply NoDup_app_inv in ND; destruct ND as (_ & ND & _).
  inversion ND as [|? ? Hn _]; subst. simpl in Hn; intuition.
Qed.

Lemma find_assoc_controller:
  forall x fs q, find_assoc x fs = Some q ->
  find_assoc x (map (fun xq => (fst xq, ctype_of_prim (snd xq))) fs) = Some (ctype_of_prim q).
Proof.
  induction fs as [|[y r] fs IH]; simpl; intros q H; [discriminate|].
  destruct (string_dec x y); [congruence|auto].
Qed.

Lemma field_type_inputs:
  forall x q, find_assoc x (nm_inputs m) = Some q ->
  field_type (composites m) (nm_in_struct m) x = Some (ctype_of_prim q).
Proof.
  intros x q H; unfold field_type, composites.
  rewrite find_composite_skip_msgs by apply in_struct_not_msg.
  unfold find_composite; simpl. destruct (string_dec (nm_in_struct m) (nm_in_struct m)); [|congruence].
  simpl; apply find_assoc_controller; auto.
Qed.

Lemma field_type_outputs:
  forall x q, find_assoc x (nm_outputs m) = Some q ->
  field_type (composites m) (nm_out_struct m) x = Some (ctype_of_prim q).
Proof.
  intros x q H; unfold field_type, composites.
  rewrite find_composite_skip_msgs by apply out_struct_not_msg.
  unfold find_composite; simpl.
  destruct (string_dec (nm_in_struct m) (nm_out_struct m)) as [E|_];
    [elim in_out_structs_differ; auto|].
  destruct (string_dec (nm_out_struct m) (nm_out_struct m)); [|congruence].
  simpl; apply find_assoc_controller; auto.
Qed.

(** The source and destination of the copy of an input relation are
    well-typed places of the input's C type. *)
Lemma input_copy_typed:
  forall ir, In ir (nm_inrels m) ->
     typeof (input_src m (make_tables m) ir) = ctype_of_prim (input_prim (make_tables m) (ir_input ir))
  /\ wt_place (composites m) (input_src m (make_tables m) ir)
  /\ typeof (input_dst m (make_tables m) ir) = ctype_of_prim (input_prim (make_tables m) (ir_input ir))
  /\ wt_place (composites m) (input_dst m (make_tables m) ir).
Proof.
  intros ir Hin. destruct (wf_inrel m ir W Hin) as (tp & q & F & S & I & R).
  destruct (leaf_path_expr_typed (tp_msg tp) (ir_path ir) q
              (Evar (msg_var (ir_topic ir)) (Tstruct (tp_msg tp))) R) as [T1 W1];
    [reflexivity|constructor|].
  unfold input_src, input_dst. rewrite (topic_msg_tables m _ _ F), (input_prim_tables m _ _ I).
  split; [exact T1|]; split; [exact W1|]. split; [reflexivity|].
  eapply wt_Efield; [constructor|reflexivity|apply field_type_inputs; auto].
Qed.

(** Same for output relations, writing into the message of a published
    topic [tp]. *)
Lemma output_copy_typed:
  forall tp o, In tp (nm_topics m) -> In o (topic_outrels (make_tables m) (tp_cname tp)) ->
     typeof (output_src m (make_tables m) o) = ctype_of_prim (output_prim (make_tables m) (or_output o))
  /\ wt_place (composites m) (output_src m (make_tables m) o)
  /\ typeof (output_dst m (tp_msg tp) o) = ctype_of_prim (output_prim (make_tables m) (or_output o))
  /\ wt_place (composites m) (output_dst m (tp_msg tp) o).
Proof.
  intros tp o Htp Ho. apply In_topic_outrels in Ho. destruct Ho as [Hin E].
  destruct (wf_outrel m o W Hin) as (tp' & q & F & S & O & R).
  rewrite E, (In_find_topic _ _ (wf_cnames_nodup m W) Htp) in F. inversion F; subst tp'.
  rewrite (output_prim_tables m _ _ O).
  destruct (leaf_path_expr_typed (tp_msg tp) (or_path o) q (deref_param command_param (tp_msg tp)) R)
    as [T1 W1]; [auto|constructor|].
  unfold output_src, output_dst, out_var_expr. rewrite (output_prim_tables m _ _ O).
  split; [reflexivity|].
  split; [eapply wt_Efield; [constructor|reflexivity|apply field_type_outputs; auto]|].
  split; auto.
Qed.

End TYPING.

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
  intros m; unfold build_defs, global_names.
  rewrite !map_app, map_fst_flat_map, !map_map.
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
  forall m id d, In (id, d) (ros_externals ++ flat_map topic_externals (nm_topics m) ++ controller_defs m) ->
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
  /\ find_def p ros_rate_sleep_name = Some (Gfun (External EF_ros_rate_sleep [] Tvoid))
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

Lemma temps_of_nodup: forall qs, NoDup (map fst (temps_of qs)).
Proof.
  intros qs. unfold temps_of. apply NoDup_map_filter.
  repeat constructor; simpl; intuition discriminate.
Qed.

(** Callbacks: for each subscribed topic, [c_callback] copies every leaf of
    [*msg] into the global [c_msg], in the order of [leaves]. *)
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
  /\ fn_body f = seq_of (map (leaf_copy (prog_types p) (Evar (msg_var c) (Tstruct M))
                                                     (deref_param msg_param M))
                             (leaves (nm_msgs m) M))
  /\ NoDup (map fst (fn_temps f))
  /\ (forall l, In l (leaves (nm_msgs m) M) ->
        find_assoc (temp_name (snd l)) (fn_temps f) = Some (ctype_of_prim (snd l))).
Proof.
  intros m p tp H Hin c M. rewrite (generate_types m p H). split.
  - apply (generate_find_def m p _ _ H). unfold build_defs; rewrite !in_app_iff.
    do 3 right; left. change (msg_var c, Gvar (Tstruct M)) with (msg_global tp). apply in_map; auto.
  - exists (callback_function m tp); repeat split.
    + apply (generate_find_def m p _ _ H). unfold build_defs; rewrite !in_app_iff.
      do 4 right; left. change (callback_name c, Gfun (Internal (callback_function m tp)))
        with (callback_def m tp). apply in_map; auto.
    + apply temps_of_nodup.
    + intros l Hl. apply temps_of_find. apply in_map; auto.
Qed.

(** ** Relation consistency (the paper's Figure 15) *)

(** The lists of source and destination expressions of the copies of
    [input_glue], one per input relation. *)
Definition gen_list_global_expr_input_glue (m : node_model) (lir : list inrel) : list expr :=
  map (input_src m (make_tables m)) lir.
Definition gen_list_controller_expr_input_glue (m : node_model) (lir : list inrel) : list expr :=
  map (input_dst m (make_tables m)) lir.

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
      expr_place c = Some (Rvar (nm_in_var m), [PField (ir_input ir)]) ->
      relation_consistency_input m lir lg lc ->
      relation_consistency_input m (ir :: lir) (g :: lg) (c :: lc).

Lemma relation_consistency_input_glue:
  forall m lir lg lc,
  lg = gen_list_global_expr_input_glue m lir ->
  lc = gen_list_controller_expr_input_glue m lir ->
  relation_consistency_input m lir lg lc.
Proof.
  intros m lir lg lc -> ->. induction lir as [|ir lir IH]; simpl; constructor; auto;
    apply expr_place_path_expr with (q := []); auto.
Qed.

(** The body of [input_glue] is the sequence of copies of the relations,
    in order: [Controller_U.In_i = c_i_msg.path_i] through a temporary. *)
Lemma input_glue_body:
  forall m,
  fn_body (input_glue_function m (make_tables m))
  = seq_of (copies (map (fun ir => input_prim (make_tables m) (ir_input ir)) (nm_inrels m))
                   (gen_list_controller_expr_input_glue m (nm_inrels m))
                   (gen_list_global_expr_input_glue m (nm_inrels m))).
Proof.
  intros m; simpl; f_equal. unfold gen_list_controller_expr_input_glue, gen_list_global_expr_input_glue.
  induction (nm_inrels m) as [|ir l IH]; simpl; auto. rewrite IH; auto.
Qed.

(** The same for one published topic with C name [c] and message [M]. *)
Definition gen_list_controller_expr_output_glue (m : node_model) (lor : list outrel) : list expr :=
  map (output_src m (make_tables m)) lor.
Definition gen_list_message_expr_output_glue (m : node_model) (M : ident) (lor : list outrel) : list expr :=
  map (output_dst m M) lor.

Inductive relation_consistency_output (m : node_model) (c : ident) :
    list outrel -> list expr -> list expr -> Prop :=
  | rco_nil:
      relation_consistency_output m c [] [] []
  | rco_cons: forall o lor s ls d ld,
      or_topic o = c ->
      expr_place s = Some (Rvar (nm_out_var m), [PField (or_output o)]) ->
      expr_place d = Some (Rderef command_param, or_path o) ->
      relation_consistency_output m c lor ls ld ->
      relation_consistency_output m c (o :: lor) (s :: ls) (d :: ld).

Lemma relation_consistency_output_glue:
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

(** The body of [output_glue_c]: zero every leaf of [*command], then the
    copies of the topic's output relations, in order. *)
Lemma output_glue_body:
  forall m tp,
  let M := tp_msg tp in
  let lor := topic_outrels (make_tables m) (tp_cname tp) in
  fn_body (output_glue_function m (make_tables m) tp)
  = Ssequence
      (seq_of (map (leaf_zero (composites m) (deref_param command_param M)) (leaves (nm_msgs m) M)))
      (seq_of (copies (map (fun o => output_prim (make_tables m) (or_output o)) lor)
                      (gen_list_message_expr_output_glue m M lor)
                      (gen_list_controller_expr_output_glue m lor))).
Proof.
  intros m tp M lor; simpl; f_equal. f_equal.
  unfold gen_list_controller_expr_output_glue, gen_list_message_expr_output_glue.
  fold lor. induction lor as [|o l IH]; simpl; auto. rewrite IH; auto.
Qed.

(** The copy of an input relation, concretely. *)
Lemma input_exprs:
  forall m ir, wf_facts m -> In ir (nm_inrels m) ->
  exists tp q,
     find_topic (nm_topics m) (ir_topic ir) = Some tp
  /\ tp_cname tp = ir_topic ir
  /\ In tp (subscribed m)
  /\ find_assoc (ir_input ir) (nm_inputs m) = Some q
  /\ resolve (nm_msgs m) (FTmsg (tp_msg tp)) (ir_path ir) = Some (FTprim q)
  /\ input_prim (make_tables m) (ir_input ir) = q
  /\ input_src m (make_tables m) ir = path_expr (composites m) (Evar (msg_var (ir_topic ir)) (Tstruct (tp_msg tp))) (ir_path ir)
  /\ input_dst m (make_tables m) ir = Efield (Evar (nm_in_var m) (Tstruct (nm_in_struct m))) (ir_input ir) (ctype_of_prim q).
Proof.
  intros m ir W Hin. destruct (wf_inrel m ir W Hin) as (tp & q & F & S & I & R).
  exists tp, q. destruct (find_topic_In _ _ _ F) as [Htp Ec].
  repeat split; auto.
  - apply in_subscribed; split; auto. unfold is_subscribed in S.
    destruct (tp_dir tp); auto; discriminate.
  - apply input_prim_tables; auto.
  - unfold input_src. rewrite (topic_msg_tables m _ _ F); auto.
  - unfold input_dst, in_var_expr. rewrite (input_prim_tables m _ _ I); auto.
Qed.

(** The copy of an output relation of a published topic, concretely. *)
Lemma output_exprs:
  forall m tp o, wf_facts m -> In tp (nm_topics m) -> In o (topic_outrels (make_tables m) (tp_cname tp)) ->
  exists q,
     In o (nm_outrels m)
  /\ or_topic o = tp_cname tp
  /\ tp_dir tp = Publish
  /\ find_assoc (or_output o) (nm_outputs m) = Some q
  /\ resolve (nm_msgs m) (FTmsg (tp_msg tp)) (or_path o) = Some (FTprim q)
  /\ output_prim (make_tables m) (or_output o) = q
  /\ output_src m (make_tables m) o = Efield (Evar (nm_out_var m) (Tstruct (nm_out_struct m))) (or_output o) (ctype_of_prim q)
  /\ output_dst m (tp_msg tp) o = path_expr (composites m) (deref_param command_param (tp_msg tp)) (or_path o).
Proof.
  intros m tp o W Htp Ho. apply In_topic_outrels in Ho. destruct Ho as [Hin E].
  destruct (wf_outrel m o W Hin) as (tp' & q & F & S & O & R).
  rewrite E, (In_find_topic _ _ (wf_cnames_nodup m W) Htp) in F. inversion F; subst tp'.
  exists q; repeat split; auto.
  - unfold is_published in S; destruct (tp_dir tp); auto; discriminate.
  - apply output_prim_tables; auto.
  - unfold output_src, out_var_expr. rewrite (output_prim_tables m _ _ O); auto.
Qed.

(** [input_glue]: the copies of the input relations, in order. *)
Theorem generate_input_glue:
  forall m p, generate m = OK p ->
  exists f,
     find_def p input_glue_name = Some (Gfun (Internal f))
  /\ fn_return f = Tvoid /\ fn_params f = [] /\ fn_vars f = []
  /\ fn_body f = seq_of (copies (map (fun ir => input_prim (make_tables m) (ir_input ir)) (nm_inrels m))
                                (gen_list_controller_expr_input_glue m (nm_inrels m))
                                (gen_list_global_expr_input_glue m (nm_inrels m)))
  /\ NoDup (map fst (fn_temps f))
  /\ (forall ir, In ir (nm_inrels m) ->
        find_assoc (temp_name (input_prim (make_tables m) (ir_input ir))) (fn_temps f)
        = Some (ctype_of_prim (input_prim (make_tables m) (ir_input ir)))).
Proof.
  intros m p H. exists (input_glue_function m (make_tables m)); repeat split.
  - apply (generate_find_def m p _ _ H). unfold build_defs; rewrite !in_app_iff.
    do 5 right; left; simpl; auto.
  - apply input_glue_body.
  - apply temps_of_nodup.
  - intros ir Hir. apply temps_of_find. apply in_map_iff; eauto.
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
  /\ fn_body f
     = Ssequence
         (seq_of (map (leaf_zero (prog_types p) (deref_param command_param M)) (leaves (nm_msgs m) M)))
         (seq_of (copies (map (fun o => output_prim (make_tables m) (or_output o)) lor)
                         (gen_list_message_expr_output_glue m M lor)
                         (gen_list_controller_expr_output_glue m lor)))
  /\ NoDup (map fst (fn_temps f))
  /\ (forall o, In o lor ->
        find_assoc (temp_name (output_prim (make_tables m) (or_output o))) (fn_temps f)
        = Some (ctype_of_prim (output_prim (make_tables m) (or_output o)))).
Proof.
  intros m p tp H Hin c M lor. exists (output_glue_function m (make_tables m) tp); repeat split.
  - apply (generate_find_def m p _ _ H). unfold build_defs; rewrite !in_app_iff.
    do 6 right; left. change (output_glue_name c, Gfun (Internal (output_glue_function m (make_tables m) tp)))
      with (output_glue_def m (make_tables m) tp). apply in_map; auto.
  - rewrite (generate_types m p H). apply output_glue_body.
  - apply temps_of_nodup.
  - intros o Ho. apply temps_of_find. apply in_map_iff; eauto.
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

(** ** Valid assignment via type checking (the paper's Figure 16) *)

(** The paper's check that the two sides of the copies of [input_glue]
    have equal types. *)
Fixpoint type_checking_input_glue (ltype_global_fields ltype_controller_fields : list type) : bool :=
  match ltype_global_fields, ltype_controller_fields with
  | [], [] => true
  | tg :: ltypeg, tc :: ltypec => type_eqb tg tc && type_checking_input_glue ltypeg ltypec
  | _, _ => false
  end.

Lemma type_checking_input_glue_sound:
  forall l1 l2, type_checking_input_glue l1 l2 = true -> l1 = l2.
Proof.
  induction l1 as [|t1 l1 IH]; intros [|t2 l2]; simpl; try congruence.
  rewrite andb_true_iff, type_eqb_true; intros [-> E]. f_equal; auto.
Qed.

(** The generator emits [input_glue] only for models where the check
    succeeds. *)
Lemma type_checking_input_glue_generated:
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

Lemma type_checking_output_glue_generated:
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

Definition wt_rhs (ce : list composite_definition) (temps : list (ident * type)) (e : expr) : Prop :=
  match e with
  | Etempvar x t => find_assoc x temps = Some t
  | Econst_int _ _ | Econst_long _ _ | Econst_float _ _ | Econst_single _ _ => True
  | _ => wt_place ce e
  end.

Fixpoint valid_assignments (ce : list composite_definition) (temps : list (ident * type))
                           (s : statement) : Prop :=
  match s with
  | Sassign l r =>
      typeof l = typeof r /\ is_scalar (typeof l) = true /\ wt_place ce l /\ wt_rhs ce temps r
  | Sset x e => find_assoc x temps = Some (typeof e) /\ wt_place ce e
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
  destruct F as [F|[F|[F|[F|[F|[F|[F|F]]]]]]].
  - simpl in F; intuition discriminate.
  - apply in_flat_map in F; destruct F as (tp & _ & F).
    unfold topic_externals in F; destruct (tp_dir tp); simpl in F; intuition discriminate.
  - simpl in F; intuition discriminate.
  - apply in_map_iff in F; destruct F as (tp & E & _); discriminate.
  - (* callbacks *)
    apply in_map_iff in F; destruct F as (tp & E & Htp); inversion E; subst f; clear E.
    simpl. apply valid_assignments_seq. intros st Hst.
    apply in_map_iff in Hst; destruct Hst as ([pa q] & <- & Hl).
    apply leaves_spec in Hl as R; auto.
    destruct (leaf_path_expr_typed m _ _ _ (Evar (msg_var (tp_cname tp)) (Tstruct (tp_msg tp))) R)
      as [T1 W1]; auto; [constructor|].
    destruct (leaf_path_expr_typed m _ _ _ (deref_param msg_param (tp_msg tp)) R)
      as [T2 W2]; auto; [constructor|].
    apply valid_copy; auto. apply temps_of_find. apply in_map_iff; exists (pa, q); auto.
  - (* input_glue *)
    simpl in F; destruct F as [E|[]]; inversion E; subst f; clear E.
    rewrite input_glue_body. apply valid_copies. intros i q d s E1 E2 E3.
    destruct (nth_error_map3 _ _ _ _ _ _ _ _ _ E1 E2 E3) as (ir & Hir & -> & -> & ->).
    destruct (input_copy_typed m W ir Hir) as (? & ? & ? & ?).
    repeat split; auto. apply temps_of_find. apply in_map_iff; eauto.
  - (* output_glue *)
    apply in_map_iff in F; destruct F as (tp & E & Htp); inversion E; subst f; clear E.
    apply in_published in Htp; destruct Htp as [Htp _].
    rewrite output_glue_body. split.
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
      repeat split; auto. apply temps_of_find. apply in_map_iff; eauto.
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
    topic's global message, [input_glue] only fields of [Controller_U],
    [output_glue_c] only through its pointer parameter [command]; [loop]
    and [main] assign nothing. *)
Theorem generate_assigned_places:
  forall m p id f, generate m = OK p -> find_def p id = Some (Gfun (Internal f)) ->
  forall pl, In pl (assigned_places (fn_body f)) ->
     (exists tp path, In tp (subscribed m) /\ id = callback_name (tp_cname tp)
                      /\ pl = Some (Rvar (msg_var (tp_cname tp)), path))
  \/ (exists x, id = input_glue_name /\ pl = Some (Rvar (nm_in_var m), [PField x]))
  \/ (exists tp path, In tp (published m) /\ id = output_glue_name (tp_cname tp)
                      /\ pl = Some (Rderef command_param, path)).
Proof.
  intros m p id f H F pl Hpl.
  apply find_def_build with (m := m) in F; auto.
  unfold build_defs in F; rewrite !in_app_iff in F.
  destruct F as [F|[F|[F|[F|[F|[F|[F|F]]]]]]].
  - simpl in F; intuition discriminate.
  - apply in_flat_map in F; destruct F as (tp & _ & F).
    unfold topic_externals in F; destruct (tp_dir tp); simpl in F; intuition discriminate.
  - simpl in F; intuition discriminate.
  - apply in_map_iff in F; destruct F as (tp & E & _); discriminate.
  - apply in_map_iff in F; destruct F as (tp & E & Htp); inversion E; subst; clear E.
    left. simpl in Hpl. rewrite assigned_places_seq in Hpl.
    apply in_flat_map in Hpl; destruct Hpl as (st & Hst & Hpl).
    apply in_map_iff in Hst; destruct Hst as ([pa q] & <- & _).
    simpl in Hpl; destruct Hpl as [<-|[]].
    exists tp, pa; repeat split; auto. apply expr_place_path_expr with (q := []); auto.
  - simpl in F; destruct F as [E|[]]; inversion E; subst; clear E.
    right; left. rewrite input_glue_body in Hpl. apply assigned_places_copies in Hpl.
    destruct Hpl as (d & Hd & ->). unfold gen_list_controller_expr_input_glue in Hd.
    apply in_map_iff in Hd; destruct Hd as (ir & <- & _).
    exists (ir_input ir); split; auto.
  - apply in_map_iff in F; destruct F as (tp & E & Htp); inversion E; subst; clear E.
    right; right. rewrite output_glue_body in Hpl. simpl in Hpl. apply in_app_iff in Hpl.
    destruct Hpl as [Hpl|Hpl].
    + rewrite assigned_places_seq in Hpl. apply in_flat_map in Hpl.
      destruct Hpl as (st & Hst & Hpl).
      apply in_map_iff in Hst; destruct Hst as ([pa q] & <- & _).
      simpl in Hpl; destruct Hpl as [<-|[]].
      exists tp, pa; repeat split; auto. apply expr_place_path_expr with (q := []); auto.
    + apply assigned_places_copies in Hpl. destruct Hpl as (d & Hd & ->).
      unfold gen_list_message_expr_output_glue in Hd.
      apply in_map_iff in Hd; destruct Hd as (o & <- & _).
      exists tp, (or_path o); repeat split; auto. apply expr_place_path_expr with (q := []); auto.
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
  ++ map (fun tp => callback_name (tp_cname tp)) (subscribed m)
  ++ [input_glue_name]
  ++ map (fun tp => output_glue_name (tp_cname tp)) (published m)
  ++ [loop_name; main_name]
  ++ local_names m.

Lemma names_split:
  forall m,
  global_names m ++ local_names m
  = ([ros_init_name; ros_ok_name; ros_spinOnce_name; ros_rate_sleep_name]
     ++ flat_map topic_extern_names (nm_topics m) ++ [init_name m; step_name m])
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
  intros m tp H; unfold names_after_controller; rewrite !in_app_iff; right; left.
  apply in_map_iff; eauto.
Qed.

Lemma cmd_var_in_after:
  forall m tp, In tp (published m) -> In (cmd_var (tp_cname tp)) (names_after_controller m).
Proof.
  intros m tp H; unfold names_after_controller, local_names; rewrite !in_app_iff.
  do 7 right. apply in_map_iff; eauto.
Qed.

(** Preservation: no generated function other than [input_glue] assigns
    (a part of) [Controller_U]. *)
Theorem generate_inputs_written_only_by_input_glue:
  forall m p id f, generate m = OK p -> find_def p id = Some (Gfun (Internal f)) ->
  id <> input_glue_name ->
  forall pl, In pl (assigned_places (fn_body f)) ->
  exists r path, pl = Some (r, path) /\ r <> Rvar (nm_in_var m).
Proof.
  intros m p id f H F Hid pl Hpl.
  assert (W: wf_facts m) by (apply wf_facts_intro, (generate_sound m p H)).
  destruct (wf_controller_vars_fresh m W) as (_ & NU & _).
  destruct (generate_assigned_places m p id f H F pl Hpl)
    as [(tp & pa & Htp & _ & ->)|[(x & E & _)|(tp & pa & _ & _ & ->)]].
  - exists (Rvar (msg_var (tp_cname tp))), pa; split; auto.
    intros E; inversion E. apply NU; rewrite <- H1; apply msg_var_in_after; auto.
  - congruence.
  - exists (Rderef command_param), pa; split; auto; discriminate.
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
    as [(tp & pa & Htp & _ & ->)|[(x & _ & ->)|(tp & pa & _ & _ & ->)]].
  - exists (Rvar (msg_var (tp_cname tp))), pa; split; auto.
    intros E; inversion E. apply NY; rewrite <- H1; apply msg_var_in_after; auto.
  - exists (Rvar (nm_in_var m)), [PField x]; split; auto. intros E; inversion E; auto.
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
  destruct F as [F|[F|[F|[F|[F|[F|[F|F]]]]]]].
  - simpl in F; intuition discriminate.
  - apply in_flat_map in F; destruct F as (tp & _ & F).
    unfold topic_externals in F; destruct (tp_dir tp); simpl in F; intuition discriminate.
  - simpl in F; intuition discriminate.
  - apply in_map_iff in F; destruct F as (tp & E & _); discriminate.
  - exfalso. apply in_map_iff in F; destruct F as (tp & E & Htp); inversion E; subst; clear E.
    simpl in T. rewrite stmt_takes_addr_seq in T. apply existsb_exists in T.
    destruct T as (st & Hst & T). apply in_map_iff in Hst; destruct Hst as ([pa q] & <- & _).
    unfold leaf_copy in T; simpl fst in T; simpl snd in T.
    rewrite copy_takes_no_addr in T; auto; discriminate.
  - exfalso. simpl in F; destruct F as [E|[]]; inversion E; subst; clear E.
    rewrite input_glue_body, stmt_takes_addr_seq, copies_take_no_addr in T; [discriminate| |].
    + intros d Hd. unfold gen_list_controller_expr_input_glue in Hd.
      apply in_map_iff in Hd; destruct Hd as (ir & <- & _). unfold input_dst; auto.
    + intros s Hs. unfold gen_list_global_expr_input_glue in Hs.
      apply in_map_iff in Hs; destruct Hs as (ir & <- & _). unfold input_src.
      rewrite expr_takes_addr_path; auto.
  - exfalso. apply in_map_iff in F; destruct F as (tp & E & Htp); inversion E; subst; clear E.
    rewrite output_glue_body in T. simpl in T. rewrite !stmt_takes_addr_seq in T.
    apply orb_true_iff in T; destruct T as [T|T].
    + apply existsb_exists in T. destruct T as (st & Hst & T).
      apply in_map_iff in Hst; destruct Hst as ([pa q] & <- & _).
      unfold leaf_zero in T; simpl in T. rewrite expr_takes_addr_path in T. simpl in T.
      destruct q; discriminate.
    + rewrite copies_take_no_addr in T; [discriminate| |].
      * intros d Hd. unfold gen_list_message_expr_output_glue in Hd.
        apply in_map_iff in Hd; destruct Hd as (o & <- & _). unfold output_dst.
        rewrite expr_takes_addr_path; auto.
      * intros s Hs. unfold gen_list_controller_expr_output_glue in Hs.
        apply in_map_iff in Hs; destruct Hs as (o & <- & _). unfold output_src; auto.
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

(** ** Facts for the semantic proofs *)

Lemma NoDup_app_intro:
  forall (A : Type) (l1 l2 : list A),
  NoDup l1 -> NoDup l2 -> (forall x, In x l1 -> ~ In x l2) -> NoDup (l1 ++ l2).
Proof.
  induction l1 as [|a l1 IH]; simpl; intros l2 N1 N2 D; auto.
  inversion N1 as [|? ? Hn N1']; subst. constructor.
  - rewrite in_app_iff; intros [H|H]; [contradiction|eapply D; eauto].
  - apply IH; auto.
Qed.

Lemma map_fst_prefix_leaves:
  forall s l, map fst (prefix_leaves s l) = map (cons s) (map fst l).
Proof. intros; unfold prefix_leaves; rewrite !map_map; auto. Qed.

Lemma NoDup_map_cons:
  forall (s : pstep) (l : list path), NoDup l -> NoDup (map (cons s) l).
Proof.
  induction l as [|x l IH]; simpl; intros N; constructor.
  - inversion N; subst. rewrite in_map_iff; intros (y & E & Hy). inversion E; subst; contradiction.
  - inversion N; auto.
Qed.

(** Blocks of leaves under distinct first steps have distinct paths. *)
Lemma NoDup_flat_map_prefix:
  forall (A : Type) (key : A -> pstep) (g : A -> list (path * prim)) l,
  NoDup (map key l) -> (forall a, In a l -> NoDup (map fst (g a))) ->
  NoDup (map fst (flat_map (fun a => prefix_leaves (key a) (g a)) l)).
Proof.
  induction l as [|a l IH]; simpl; intros N G; [constructor|].
  inversion N as [|? ? Hn N']; subst.
  rewrite map_app. apply NoDup_app_intro.
  - rewrite map_fst_prefix_leaves. apply NoDup_map_cons; auto.
  - apply IH; auto.
  - intros x Hx Hx'. rewrite map_fst_prefix_leaves in Hx. apply in_map_iff in Hx.
    destruct Hx as (p & <- & _). apply in_map_iff in Hx'.
    destruct Hx' as ([p' q'] & E & Hp'). simpl in E. apply in_flat_map in Hp'.
    destruct Hp' as (b & Hb & Hp'). apply In_prefix_leaves in Hp'.
    destruct Hp' as (p'' & E' & _). subst p'. inversion E'; subst.
    apply Hn. rewrite H0. apply in_map; auto.
Qed.

Lemma NoDup_map_inj:
  forall (A B : Type) (f : A -> B) l, (forall a b, f a = f b -> a = b) -> NoDup l -> NoDup (map f l).
Proof.
  induction l as [|x l IH]; simpl; intros I N; constructor.
  - inversion N; subst. rewrite in_map_iff; intros (y & E & Hy). apply I in E; subst; contradiction.
  - inversion N; auto.
Qed.

Lemma NoDup_zrange: forall n, NoDup (map PIndex (zrange n)).
Proof.
  intros n; unfold zrange. rewrite map_map.
  generalize (seq_NoDup (Z.to_nat n) 0). generalize (seq 0 (Z.to_nat n)).
  induction l as [|k l IH]; simpl; intros N; constructor.
  - inversion N; subst. rewrite in_map_iff; intros (j & E & Hj). inversion E.
    apply Nat2Z.inj in H0; subst; contradiction.
  - inversion N; auto.
Qed.

Lemma ftype_leaves_nodup:
  forall ml, (forall id, NoDup (map fst (ml id))) ->
  forall t, NoDup (map fst (ftype_leaves ml t)).
Proof.
  intros ml H; induction t as [q|id|t IH n]; simpl; auto.
  - repeat constructor; simpl; tauto.
  - apply (NoDup_flat_map_prefix Z PIndex (fun _ => ftype_leaves ml t)); auto.
    apply NoDup_zrange.
Qed.

Lemma scope_leaves_nodup:
  forall scope, scope_ok scope -> forall id, NoDup (map fst (scope_leaves scope id)).
Proof.
  induction 1 as [|md rest Hn ND Hf Hs IH]; intros id; simpl; [constructor|].
  destruct (ident_eqb (md_name md) id); auto.
  unfold fields_leaves.
  apply (NoDup_flat_map_prefix _ (fun ft => PField (fst ft)) (fun ft => ftype_leaves (scope_leaves rest) (snd ft))).
  - rewrite <- (map_map fst PField). apply NoDup_map_inj; auto.
    intros a b E; inversion E; auto.
  - intros; apply ftype_leaves_nodup; auto.
Qed.

(** Each leaf of a message appears once: a callback copies every leaf
    exactly once, and [output_glue] zeroes every leaf exactly once. *)
Theorem leaves_nodup:
  forall m id, wf_facts m -> NoDup (map fst (leaves (nm_msgs m) id)).
Proof. intros m id W; apply scope_leaves_nodup, wf_scope_ok; auto. Qed.

Lemma wf_inputs_fed_rel:
  forall m x q, wf_facts m -> In (x, q) (nm_inputs m) ->
  exists ir, In ir (nm_inrels m) /\ ir_input ir = x.
Proof.
  intros m x q W H. generalize (wf_inputs_fed m W x q H); intros Hx.
  apply in_map_iff in Hx; destruct Hx as (ir & E & Hir); eauto.
Qed.

(** A published field is fed by at most one output relation. *)
Lemma wf_topic_outrels_paths_nodup:
  forall m c, wf_facts m -> NoDup (map or_path (topic_outrels (make_tables m) c)).
Proof.
  intros m c W. generalize (wf_out_targets m W). rewrite tables_outrels.
  induction (nm_outrels m) as [|o l IH]; simpl; intros N; [constructor|].
  inversion N as [|? ? Hn N']; subst.
  destruct (ident_eqb (or_topic o) c) eqn:E; simpl; auto. constructor; auto.
  intros Hin. apply in_map_iff in Hin. destruct Hin as (o' & Ep & Ho').
  apply filter_In in Ho'. destruct Ho' as [Ho' Ec]. apply Hn.
  apply in_map_iff. exists o'; split; auto.
  apply ident_eqb_true in E; apply ident_eqb_true in Ec. congruence.
Qed.
