(** * Facts about node models and the generator's building blocks *)

(** The lemmas that the proofs about generated programs
    ([Generatorproof], [Copyproof], [Glueproof], [Loopproof]) share, none
    of which mentions [generate] itself:
    - generic lemmas on lists, association lists, the error monad and the
      checks of [Wellformed] ([nodup_keys_NoDup], [check_all_ok], ...);
    - the facts that well-formedness gives ([wf_facts], [wf_facts_intro]);
    - the meaning of the lookup tables ([tables_topics], [tables_inputs],
      [tables_outputs], [tables_outrels]);
    - messages: scopes, the resolution of a model path, and the leaves of
      a message: exactly the paths that resolve to a primitive
      ([leaves_spec]), each once ([leaves_nodup]);
    - the C type of a generated access [e.p] ([typeof_path_expr]), the
      places that accesses designate, and the typing of the copies of the
      input and output glue ([input_copy_typed], [output_copy_typed]). *)

From Coq Require Import String Ascii List ZArith Bool Lia.
From ROSGen Require Import Errors Syntax Values Maps NodeModel Wellformed Generator.
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

(** ** What well-formedness gives *)

Record wf_facts (m : node_model) : Prop := {
  wf_period: (0 < nm_period_ms m)%Z;
  wf_names_valid: forall x, In x (c_names m) -> valid_ident x = true;
  wf_names_nodup: NoDup (global_names m ++ local_names m);
  wf_structs_nodup: NoDup (struct_names m);
  wf_msgs: msgs_ok [] (nm_msgs m) = true;
  wf_inputs_nonempty: nm_inputs m <> [];
  wf_inputs_nodup: NoDup (map fst (nm_inputs m));
  wf_inputs_ok: forall xt, In xt (nm_inputs m) -> ctrl_ftype_ok (snd xt) = true;
  wf_outputs_nonempty: nm_outputs m <> [];
  wf_outputs_nodup: NoDup (map fst (nm_outputs m));
  wf_outputs_ok: forall xt, In xt (nm_outputs m) -> ctrl_ftype_ok (snd xt) = true;
  wf_cnames_nodup: NoDup (map tp_cname (nm_topics m));
  wf_rosnames_nodup: NoDup (map tp_name (nm_topics m));
  wf_topics: forall tp, In tp (nm_topics m) -> topic_ok (nm_msgs m) tp = true;
  wf_inrels: forall ir, In ir (nm_inrels m) -> inrel_ok m (make_tables m) ir = true;
  wf_timeouts: forall ct, In ct (nm_timeouts m) -> timeout_ok m (make_tables m) ct = true;
  wf_timeouts_nodup: NoDup (map fst (nm_timeouts m));
  wf_drels: forall dr, In dr (nm_drels m) -> drel_ok m (make_tables m) dr = true;
  wf_fed_nodup: NoDup (fed_list m);
  wf_inputs_fed: forall x p q, In (x, p, q) (ctrl_leaves (nm_inputs m)) -> In (x, p) (fed_list m);
  wf_fallbacks: forall xv, In xv (nm_fallbacks m) -> fallback_ok m (make_tables m) xv = true;
  wf_fallbacks_nodup: NoDup (map fst (nm_fallbacks m));
  wf_outrels: forall o, In o (nm_outrels m) -> outrel_ok m (make_tables m) o = true;
  wf_out_targets: NoDup (map (fun o => (or_topic o, or_path o)) (nm_outrels m));
  wf_time_msg: nm_stamps m <> [] -> time_msg_ok (nm_msgs m) = true;
  wf_stamps: forall st, In st (nm_stamps m) -> stamp_ok m (make_tables m) st = true;
  wf_stamps_nodup: NoDup (map fst (nm_stamps m));
  wf_stamp_froms: forall sf, In sf (nm_stamp_from m) -> stamp_from_ok m (make_tables m) sf = true;
  wf_stamp_from_nodup: NoDup (map fst (nm_stamp_from m));
  wf_strings: forall st, In st (nm_strings m) -> string_ok m (make_tables m) st = true;
  wf_strings_nodup: NoDup (map string_target (nm_strings m))
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
  - intros x p q Hin.
    match goal with Hf : forall l, In l (ctrl_leaves (nm_inputs m)) -> tmem _ _ _ = true |- _ =>
      generalize (Hf (x, p, q) Hin) end.
    unfold fed_inputs; rewrite (tmem_of_list _ _ enc_target_inj); auto.
  - intros NE. destruct (nm_stamps m) as [|st l] eqn:E; [congruence|].
    repeat match goal with H : context [nm_stamps m] |- _ => rewrite E in H end.
    simpl in *. auto.
Qed.

Lemma wf_inrel_inputs_nodup: forall m, wf_facts m -> NoDup (map (fun ir => (ir_input ir, ir_elem ir)) (nm_inrels m)).
Proof.
  intros m W. generalize (wf_fed_nodup m W). unfold fed_list. intros N.
  apply NoDup_app_inv in N. tauto.
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
  forall m x t p q, find_assoc x (nm_inputs m) = Some t -> ctrl_prim t p = Some q ->
  input_prim (make_tables m) x p = q.
Proof. intros m x t p q H Q; unfold input_prim, leaf_prim; rewrite tables_inputs, H, Q; auto. Qed.

Lemma output_prim_tables:
  forall m x t p q, find_assoc x (nm_outputs m) = Some t -> ctrl_prim t p = Some q ->
  output_prim (make_tables m) x p = q.
Proof. intros m x t p q H Q; unfold output_prim, leaf_prim; rewrite tables_outputs, H, Q; auto. Qed.

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
  exists tp t q,
     find_topic (nm_topics m) (ir_topic ir) = Some tp /\ is_subscribed tp = true
  /\ find_assoc (ir_input ir) (nm_inputs m) = Some t /\ ctrl_prim t (ir_elem ir) = Some q
  /\ resolve (nm_msgs m) (FTmsg (tp_msg tp)) (ir_path ir) = Some (FTprim q).
Proof.
  intros m ir W Hin. generalize (wf_inrels m W ir Hin); unfold inrel_ok.
  rewrite tables_topics, tables_inputs.
  destruct (find_topic (nm_topics m) (ir_topic ir)) as [tp|]; [|discriminate].
  destruct (find_assoc (ir_input ir) (nm_inputs m)) as [t|]; [|rewrite andb_false_r; discriminate].
  destruct (ctrl_prim t (ir_elem ir)) as [q|] eqn:Q; [|rewrite andb_false_r; discriminate].
  destruct (resolve_prim (nm_msgs m) (FTmsg (tp_msg tp)) (ir_path ir)) as [q'|] eqn:R;
    [|rewrite andb_false_r; discriminate].
  rewrite andb_true_iff, prim_eqb_true; intros [S <-].
  exists tp, t, q'; repeat split; auto. apply resolve_prim_inv; auto.
Qed.

Lemma wf_outrel:
  forall m o, wf_facts m -> In o (nm_outrels m) ->
  exists tp t q,
     find_topic (nm_topics m) (or_topic o) = Some tp /\ is_published tp = true
  /\ find_assoc (or_output o) (nm_outputs m) = Some t /\ ctrl_prim t (or_elem o) = Some q
  /\ resolve (nm_msgs m) (FTmsg (tp_msg tp)) (or_path o) = Some (FTprim q).
Proof.
  intros m o W Hin. generalize (wf_outrels m W o Hin); unfold outrel_ok.
  rewrite tables_topics, tables_outputs.
  destruct (find_assoc (or_output o) (nm_outputs m)) as [t|]; [|discriminate].
  destruct (ctrl_prim t (or_elem o)) as [q|] eqn:Q; [|discriminate].
  destruct (find_topic (nm_topics m) (or_topic o)) as [tp|]; [|discriminate].
  destruct (resolve_prim (nm_msgs m) (FTmsg (tp_msg tp)) (or_path o)) as [q'|] eqn:R;
    [|rewrite andb_false_r; discriminate].
  rewrite andb_true_iff, prim_eqb_true; intros [S <-].
  exists tp, t, q'; repeat split; auto. apply resolve_prim_inv; auto.
Qed.

(** Rule 4.12: a derived input is about a subscribed topic and feeds a
    controller input of its type. *)
Lemma wf_drel:
  forall m dr, wf_facts m -> In dr (nm_drels m) ->
  exists tp,
     find_topic (nm_topics m) (dr_topic dr) = Some tp /\ is_subscribed tp = true
  /\ find_assoc (dr_input dr) (nm_inputs m) = Some (FTprim (derived_prim (dr_kind dr))).
Proof.
  intros m dr W Hin. generalize (wf_drels m W dr Hin); unfold drel_ok.
  rewrite tables_topics, tables_inputs.
  destruct (find_topic (nm_topics m) (dr_topic dr)) as [tp|]; [|discriminate].
  destruct (find_assoc (dr_input dr) (nm_inputs m)) as [[q| |]|]; try (rewrite andb_false_r; discriminate).
  rewrite andb_true_iff, prim_eqb_true. intros [S <-]. eauto.
Qed.

(** A fallback value is a value of its input's type, and the input is
    fed by an input relation of a topic with a timeout. *)
Lemma wf_fallback:
  forall m x v, wf_facts m -> In (x, v) (nm_fallbacks m) ->
  exists q ir t,
     find_assoc x (nm_inputs m) = Some (FTprim q) /\ val_has_type v (ctype_of_prim q)
  /\ In ir (nm_inrels m) /\ ir_input ir = x /\ In (ir_topic ir, t) (nm_timeouts m).
Proof.
  intros m x v W Hin. generalize (wf_fallbacks m W (x, v) Hin); unfold fallback_ok; cbn [fst snd].
  rewrite tables_inputs. destruct (find_assoc x (nm_inputs m)) as [[q| |]|]; try discriminate.
  rewrite andb_true_iff, val_has_typeb_correct, existsb_exists. intros [T (ir & Hir & E)].
  rewrite andb_true_iff, ident_eqb_true, existsb_exists in E. destruct E as [Ex ((c & t) & Hct & Ec)].
  apply ident_eqb_true in Ec. simpl in Ec. subst c. exists q, ir, t; auto.
Qed.

(** A timeout is on a subscribed topic, from the period to a day. *)
Lemma wf_timeout:
  forall m c t, wf_facts m -> In (c, t) (nm_timeouts m) ->
  exists tp, find_topic (nm_topics m) c = Some tp /\ is_subscribed tp = true
          /\ (nm_period_ms m <= t <= max_timeout_ms)%Z.
Proof.
  intros m c t W Hin. generalize (wf_timeouts m W (c, t) Hin); unfold timeout_ok; cbn [fst snd].
  rewrite tables_topics. destruct (find_topic (nm_topics m) c) as [tp|]; [|discriminate].
  rewrite !andb_true_iff, !Z.leb_le. intros [[S L] U]. exists tp; auto.
Qed.

(** The number of input relations and derived inputs that feed the
    leaf [p] of controller input [x]. *)
Definition target_eqb (a b : ident * path) : bool := ident_eqb (fst a) (fst b) && path_eqb (snd a) (snd b).

Lemma target_eqb_true: forall a b, target_eqb a b = true <-> a = b.
Proof.
  intros [x p] [y q]; unfold target_eqb; simpl. rewrite andb_true_iff, ident_eqb_true, path_eqb_iff.
  split; [intros [-> ->]; auto|intros E; inversion E; auto].
Qed.

Definition feeds (m : node_model) (x : ident) (p : path) : nat :=
  length (filter (fun y => target_eqb y (x, p)) (fed_list m)).

Lemma filter_nodup_single:
  forall (l : list (ident * path)) x, NoDup l -> In x l -> filter (fun y => target_eqb y x) l = [x].
Proof.
  induction l as [|y l IH]; simpl; intros x ND H; [contradiction|].
  inversion ND as [|? ? Hn ND']; subst.
  destruct (target_eqb y x) eqn:E.
  - apply target_eqb_true in E; subst. f_equal.
    destruct (filter (fun y => target_eqb y x) l) as [|y' l'] eqn:F; auto.
    assert (In y' (filter (fun y => target_eqb y x) l)) by (rewrite F; simpl; auto).
    apply filter_In in H0; destruct H0 as [H0 E']. apply target_eqb_true in E'. subst. contradiction.
  - destruct H as [H|H]; [subst; rewrite (proj2 (target_eqb_true x x) eq_refl) in E; discriminate|].
    apply IH; auto.
Qed.

(** Every leaf of every controller input is fed exactly once, by an
    input relation or a derived input. *)
Lemma wf_feeds:
  forall m, wf_facts m -> forall x p q, In (x, p, q) (ctrl_leaves (nm_inputs m)) -> feeds m x p = 1%nat.
Proof.
  intros m W x p q H. unfold feeds. rewrite filter_nodup_single; auto.
  - apply wf_fed_nodup; auto.
  - apply (wf_inputs_fed m W x p q H).
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

(** The leaves of a controller field: the field itself if it is a
    primitive, one element [[i]] if it is an array. *)
Lemma ctrl_leaf_cases:
  forall t p q, ctrl_ftype_ok t = true -> ctrl_prim t p = Some q ->
  (t = FTprim q /\ p = [])
  \/ (exists n i, t = FTarray (FTprim q) n /\ p = [PIndex i] /\ (0 <= i < n)%Z).
Proof.
  unfold ctrl_prim, resolve_prim. intros t p q OK R.
  destruct t as [q'| |[q'| |] n]; simpl in OK; try discriminate.
  - destruct p as [|[f|i] p]; simpl in R; try discriminate. inversion R; auto.
  - destruct p as [|[f|i] p]; simpl in R; try discriminate.
    destruct ((0 <=? i) && (i <? n))%Z eqn:B; [|discriminate].
    destruct p as [|s p]; simpl in R; [|destruct s; discriminate].
    inversion R; subst. right. exists n, i. apply andb_true_iff in B as [B1 B2].
    apply Z.leb_le in B1; apply Z.ltb_lt in B2. auto.
Qed.

(** A leaf of a controller field resolves the same in any message list. *)
Lemma ctrl_leaf_resolve:
  forall msgs seen t p q, ctrl_ftype_ok t = true -> ctrl_prim t p = Some q ->
  ftype_ok seen t = true /\ resolve msgs t p = Some (FTprim q).
Proof.
  intros msgs seen t p q OK R.
  destruct (ctrl_leaf_cases t p q OK R) as [[-> ->]|(n & i & -> & -> & B)]; simpl; auto.
  simpl in OK. rewrite OK. split; auto.
  replace ((0 <=? i) && (i <? n))%Z with true; auto.
  symmetry; apply andb_true_iff; split; [apply Z.leb_le|apply Z.ltb_lt]; lia.
Qed.

(** A leaf of a controller field has the C type of its primitive. *)
Lemma ctrl_prim_type_of_path:
  forall ce p t q, ctrl_prim t p = Some q -> type_of_path ce (ctype_of_ftype t) p = Some (ctype_of_prim q).
Proof.
  unfold ctrl_prim, resolve_prim. intros ce. induction p as [|[f|i] p IH]; intros t q H; simpl in *.
  - destruct t; try discriminate. inversion H; auto.
  - destruct t; simpl in H; discriminate.
  - destruct t; simpl in H |- *; try discriminate. destruct (_ && _); [|discriminate]. apply IH; auto.
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
  forall x fs t, find_assoc x fs = Some t ->
  find_assoc x (map (fun xt => (fst xt, ctype_of_ftype (snd xt))) fs) = Some (ctype_of_ftype t).
Proof.
  induction fs as [|[y r] fs IH]; simpl; intros q H; [discriminate|].
  destruct (string_dec x y); [congruence|auto].
Qed.

Lemma field_type_inputs:
  forall x q, find_assoc x (nm_inputs m) = Some q ->
  field_type (composites m) (nm_in_struct m) x = Some (ctype_of_ftype q).
Proof.
  intros x q H; unfold field_type, composites.
  rewrite find_composite_skip_msgs by apply in_struct_not_msg.
  unfold find_composite; simpl. destruct (string_dec (nm_in_struct m) (nm_in_struct m)); [|congruence].
  simpl; apply find_assoc_controller; auto.
Qed.

Lemma field_type_outputs:
  forall x q, find_assoc x (nm_outputs m) = Some q ->
  field_type (composites m) (nm_out_struct m) x = Some (ctype_of_ftype q).
Proof.
  intros x q H; unfold field_type, composites.
  rewrite find_composite_skip_msgs by apply out_struct_not_msg.
  unfold find_composite; simpl.
  destruct (string_dec (nm_in_struct m) (nm_out_struct m)) as [E|_];
    [elim in_out_structs_differ; auto|].
  destruct (string_dec (nm_out_struct m) (nm_out_struct m)); [|congruence].
  simpl; apply find_assoc_controller; auto.
Qed.

(** The leaf [p] of the controller input [x] of type [t] has the C type
    of its primitive. *)
Lemma input_leaf_type:
  forall x t p q, find_assoc x (nm_inputs m) = Some t -> ctrl_prim t p = Some q ->
  type_of_path (composites m) (Tstruct (nm_in_struct m)) (PField x :: p) = Some (ctype_of_prim q).
Proof.
  intros x t p q F Q. simpl. rewrite (field_type_inputs _ _ F). apply ctrl_prim_type_of_path; auto.
Qed.

Lemma output_leaf_type:
  forall x t p q, find_assoc x (nm_outputs m) = Some t -> ctrl_prim t p = Some q ->
  type_of_path (composites m) (Tstruct (nm_out_struct m)) (PField x :: p) = Some (ctype_of_prim q).
Proof.
  intros x t p q F Q. simpl. rewrite (field_type_outputs _ _ F). apply ctrl_prim_type_of_path; auto.
Qed.

(** The source and destination of the copy of an input relation are
    well-typed places of the input's C type. *)
Lemma input_copy_typed:
  forall ir, In ir (nm_inrels m) ->
     typeof (input_src m (make_tables m) ir) = ctype_of_prim (inrel_prim (make_tables m) ir)
  /\ wt_place (composites m) (input_src m (make_tables m) ir)
  /\ typeof (input_dst m ir) = ctype_of_prim (inrel_prim (make_tables m) ir)
  /\ wt_place (composites m) (input_dst m ir).
Proof.
  intros ir Hin. destruct (wf_inrel m ir W Hin) as (tp & t & q & F & S & I & Q & R).
  destruct (leaf_path_expr_typed (tp_msg tp) (ir_path ir) q
              (Evar (msg_var (ir_topic ir)) (Tstruct (tp_msg tp))) R) as [T1 W1];
    [reflexivity|constructor|].
  unfold input_src, input_dst, inrel_prim. rewrite (topic_msg_tables m _ _ F), (input_prim_tables m _ _ _ _ I Q).
  split; [exact T1|]; split; [exact W1|].
  assert (TP := input_leaf_type _ _ _ _ I Q).
  split; [apply typeof_path_expr; auto|]. eapply path_expr_wt; [constructor|]. exact TP.
Qed.

(** The source of the copy of a direct input relation of the topic [tp]
    (rule 4.16), in its callback, is a well-typed place of the input's C
    type. *)
Lemma direct_src_typed:
  forall tp ir, In tp (nm_topics m) -> In ir (direct_of m (tp_cname tp)) ->
     typeof (path_expr (composites m) (deref_param msg_param (tp_msg tp)) (ir_path ir))
     = ctype_of_prim (inrel_prim (make_tables m) ir)
  /\ wt_place (composites m) (path_expr (composites m) (deref_param msg_param (tp_msg tp)) (ir_path ir)).
Proof.
  intros tp ir Htp Hd. apply direct_of_In in Hd. destruct Hd as (Hin & E & _).
  destruct (wf_inrel m ir W Hin) as (tp' & t & q & F & S & I & Q & R).
  rewrite E, (In_find_topic _ _ (wf_cnames_nodup m W) Htp) in F. inversion F; subst tp'.
  unfold inrel_prim. rewrite (input_prim_tables m _ _ _ _ I Q).
  apply (leaf_path_expr_typed (tp_msg tp) (ir_path ir) q); auto. constructor.
Qed.

(** Same for output relations, writing into the message of a published
    topic [tp]. *)
Lemma output_copy_typed:
  forall tp o, In tp (nm_topics m) -> In o (topic_outrels (make_tables m) (tp_cname tp)) ->
     typeof (output_src m o) = ctype_of_prim (outrel_prim (make_tables m) o)
  /\ wt_place (composites m) (output_src m o)
  /\ typeof (output_dst m (tp_msg tp) o) = ctype_of_prim (outrel_prim (make_tables m) o)
  /\ wt_place (composites m) (output_dst m (tp_msg tp) o).
Proof.
  intros tp o Htp Ho. apply In_topic_outrels in Ho. destruct Ho as [Hin E].
  destruct (wf_outrel m o W Hin) as (tp' & t & q & F & S & O & Q & R).
  rewrite E, (In_find_topic _ _ (wf_cnames_nodup m W) Htp) in F. inversion F; subst tp'.
  unfold outrel_prim. rewrite (output_prim_tables m _ _ _ _ O Q).
  destruct (leaf_path_expr_typed (tp_msg tp) (or_path o) q (deref_param command_param (tp_msg tp)) R)
    as [T1 W1]; [auto|constructor|].
  assert (TP := output_leaf_type _ _ _ _ O Q).
  unfold output_src, output_dst, out_var_expr.
  split; [apply typeof_path_expr; auto|].
  split; [eapply path_expr_wt; [constructor|]; exact TP|].
  split; auto.
Qed.

End TYPING.

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

(** Each leaf of a message appears once: a callback copies each leaf it
    reads exactly once, and [output_glue] zeroes every leaf exactly once. *)
Theorem leaves_nodup:
  forall m id, wf_facts m -> NoDup (map fst (leaves (nm_msgs m) id)).
Proof. intros m id W; apply scope_leaves_nodup, wf_scope_ok; auto. Qed.

Lemma wf_inputs_fed_rel:
  forall m x p q, wf_facts m -> In (x, p, q) (ctrl_leaves (nm_inputs m)) ->
  (exists ir, In ir (nm_inrels m) /\ ir_input ir = x /\ ir_elem ir = p)
  \/ (exists dr, In dr (nm_drels m) /\ dr_input dr = x /\ p = []).
Proof.
  intros m x p q W H. generalize (wf_inputs_fed m W x p q H); intros Hx.
  unfold fed_list in Hx. apply in_app_iff in Hx. destruct Hx as [Hx|Hx];
    apply in_map_iff in Hx; destruct Hx as (r & E & Hr); inversion E; subst; eauto.
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

(** ** Stamps (rule 4.13) *)

Lemma resolve_app:
  forall msgs p q t,
  resolve msgs t (p ++ q) = match resolve msgs t p with Some t' => resolve msgs t' q | None => None end.
Proof.
  induction p as [|s p IH]; intros q t; simpl; auto.
  destruct s as [f|i].
  - destruct t as [|id|]; auto. destruct (find_msg msgs id) as [md|]; auto.
    destruct (find_assoc f (md_fields md)); auto.
  - destruct t as [| |t' n]; auto. destruct ((0 <=? i)%Z && (i <? n)%Z); auto.
Qed.

Lemma pstep_eqb_true: forall a b, pstep_eqb a b = true -> a = b.
Proof.
  intros [f|i] [g|j]; simpl; intros H; try discriminate.
  - apply ident_eqb_true in H; subst; auto.
  - apply Z.eqb_eq in H; subst; auto.
Qed.

Lemma path_prefixb_app: forall p q, path_prefixb p (p ++ q) = true.
Proof.
  induction p as [|[f|i] p IH]; intros q; simpl; auto.
  - rewrite ident_eqb_refl; simpl; auto.
  - rewrite Z.eqb_refl; simpl; auto.
Qed.

(** ** Constant strings (rule 4.14) *)

Lemma string_msg_spec:
  forall msgs id n, string_msg msgs id = Some n ->
  exists md, find_msg msgs id = Some md
  /\ md_fields md = [("len", FTprim Puint32); ("truncated", FTprim Pbool); ("data", FTarray (FTprim Puint8) n)]
  /\ (n <= max_string)%Z.
Proof.
  intros msgs id n H. unfold string_msg in H.
  destruct (find_msg msgs id) as [md|]; [|discriminate]. exists md. split; [auto|].
  destruct (md_fields md) as [|[l t1] r]; [discriminate|].
  destruct t1 as [q1| |]; try discriminate. destruct q1; try discriminate.
  destruct r as [|[t t2] r]; [discriminate|].
  destruct t2 as [q2| |]; try discriminate. destruct q2; try discriminate.
  destruct r as [|[d t3] r]; [discriminate|].
  destruct t3 as [| |t3 k]; try discriminate. destruct t3 as [q3| |]; try discriminate.
  destruct q3; try discriminate.
  destruct r; [|discriminate].
  destruct (ident_eqb l "len" && ident_eqb t "truncated" && ident_eqb d "data" && (k <=? max_string)%Z) eqn:E;
    [|discriminate].
  inversion H; subst k. rewrite !andb_true_iff in E. destruct E as [[[El Et] Ed] Mx].
  apply ident_eqb_true in El, Et, Ed; subst l t d. apply Z.leb_le in Mx. auto.
Qed.

(** A constant string of a published topic is at a string field of its
    message, long enough: [len], [truncated] and the [n] bytes of [data]
    are leaves, the constant has at most [n] bytes, each a byte, and no
    output relation of the topic writes into the string. *)
Lemma wf_string:
  forall m tp sp bs, wf_facts m -> In tp (published m) ->
  In (tp_cname tp, (sp, bs)) (nm_strings m) ->
  exists n,
     resolve (nm_msgs m) (FTmsg (tp_msg tp)) (sp ++ [PField "len"]) = Some (FTprim Puint32)
  /\ resolve (nm_msgs m) (FTmsg (tp_msg tp)) (sp ++ [PField "truncated"]) = Some (FTprim Pbool)
  /\ (forall i, (0 <= i < n)%Z ->
        resolve (nm_msgs m) (FTmsg (tp_msg tp)) (sp ++ [PField "data"; PIndex i]) = Some (FTprim Puint8))
  /\ (Z.of_nat (length bs) <= n)%Z /\ (n <= max_string)%Z
  /\ (forall b, In b bs -> (0 <= b <= 255)%Z)
  /\ (forall o q, In o (nm_outrels m) -> or_topic o = tp_cname tp -> or_path o <> sp ++ q).
Proof.
  intros m tp sp bs W Htp Hin.
  generalize (wf_strings m W _ Hin). unfold string_ok; cbn [fst snd].
  assert (Htop: In tp (nm_topics m)) by (unfold published in Htp; apply filter_In in Htp; tauto).
  rewrite tables_topics, (In_find_topic _ tp (wf_cnames_nodup m W) Htop).
  rewrite !andb_true_iff. intros [[[_ R] B] NO].
  destruct (resolve (nm_msgs m) (FTmsg (tp_msg tp)) sp) as [[| id |]|] eqn:Rs; try discriminate.
  destruct (string_msg (nm_msgs m) id) as [n|] eqn:SM; [|discriminate].
  apply string_msg_spec in SM. destruct SM as (md & Fm & Fd & Mx).
  apply Z.leb_le in R.
  exists n. rewrite !resolve_app, Rs. simpl. rewrite Fm, Fd. simpl.
  split; [auto|split; [auto|split; [|split; [auto|split; [auto|split]]]]].
  - intros i [H1 H2]. rewrite !resolve_app, Rs. simpl. rewrite Fm, Fd. simpl.
    rewrite (proj2 (Z.leb_le 0 i) H1), (proj2 (Z.ltb_lt i n) H2). reflexivity.
  - intros b Hb. rewrite forallb_forall in B. generalize (B b Hb). unfold is_byte.
    rewrite andb_true_iff, !Z.leb_le. lia.
  - intros o q Ho Eo Ep. rewrite forallb_forall in NO. generalize (NO o Ho).
    rewrite Eo, ident_eqb_refl, Ep, path_prefixb_app. discriminate.
Qed.

Lemma In_topic_strings:
  forall m c sp bs, In (sp, bs) (topic_strings m c) <-> In (c, (sp, bs)) (nm_strings m).
Proof.
  intros m c sp bs. unfold topic_strings. rewrite in_map_iff. split.
  - intros ([c' [sp' bs']] & E & H). apply filter_In in H. destruct H as [H Ec].
    simpl in E, Ec. inversion E; subst. apply ident_eqb_true in Ec; subst; auto.
  - intros H. exists (c, (sp, bs)). split; auto. apply filter_In. split; auto. apply ident_eqb_refl.
Qed.

Lemma In_combine_zrange:
  forall (bs : list Z) i b,
  In (i, b) (combine (zrange (Z.of_nat (length bs))) bs) <->
  (0 <= i < Z.of_nat (length bs))%Z /\ nth_error bs (Z.to_nat i) = Some b.
Proof.
  intros bs i b. unfold zrange. rewrite Nat2Z.id.
  assert (G: forall k, In (i, b) (combine (map Z.of_nat (seq k (length bs))) bs) <->
                       (Z.of_nat k <= i < Z.of_nat k + Z.of_nat (length bs))%Z
                       /\ nth_error bs (Z.to_nat i - k) = Some b).
  { induction bs as [|x bs IH]; intros k; simpl.
    - split; [tauto|]. intros [H _]. lia.
    - rewrite IH. split.
      + intros [E|[H1 H2]].
        * inversion E; subst. rewrite Nat2Z.id, Nat.sub_diag. simpl. split; [lia|auto].
        * split; [lia|]. replace (Z.to_nat i - k)%nat with (S (Z.to_nat i - S k)) by lia. auto.
      + intros [H1 H2]. destruct (Z.eq_dec i (Z.of_nat k)) as [->|N].
        * left. rewrite Nat2Z.id, Nat.sub_diag in H2. simpl in H2. inversion H2; auto.
        * right. split; [lia|]. replace (Z.to_nat i - k)%nat with (S (Z.to_nat i - S k)) in H2 by lia. auto. }
  rewrite G. rewrite Nat.sub_0_r. simpl. tauto.
Qed.

(** Every store of a constant string is at a leaf of its type, of a
    value of that type. *)
Lemma string_store_leaf:
  forall m tp sp bs a, wf_facts m -> In tp (published m) ->
  In (tp_cname tp, (sp, bs)) (nm_strings m) -> In a (string_stores sp bs) ->
     resolve (nm_msgs m) (FTmsg (tp_msg tp)) (fst (fst a)) = Some (FTprim (snd (fst a)))
  /\ val_has_type (Vint (snd a)) (ctype_of_prim (snd (fst a))).
Proof.
  intros m tp sp bs a W Htp Hin Ha.
  destruct (wf_string m tp sp bs W Htp Hin) as (n & Rl & _ & Rd & Ln & Mx & Bs & _).
  unfold string_stores in Ha. destruct Ha as [<-|Ha].
  - simpl. split; [auto|].
    unfold norm_int, wrap, wrap_unsigned, bitsize. simpl. apply Z.mod_small.
    unfold max_string in Mx. lia.
  - apply in_map_iff in Ha. destruct Ha as ([i b] & <- & Hib). apply In_combine_zrange in Hib.
    destruct Hib as [Hi Hb]. simpl. split; [apply Rd; lia|].
    assert (B: In b bs) by (eapply nth_error_In; eauto). apply Bs in B.
    unfold norm_int, wrap, wrap_unsigned, bitsize. simpl. apply Z.mod_small. lia.
Qed.

(** The paths that the stores of a string write: [sp.len] and
    [sp.data[i]] for [i] below the constant's length. *)
Lemma string_stores_path:
  forall sp bs a, In a (string_stores sp bs) ->
     (fst (fst a) = sp ++ [PField "len"] /\ snd a = Z.of_nat (length bs))
  \/ exists i b, fst (fst a) = sp ++ [PField "data"; PIndex (Z.of_nat i)] /\ nth_error bs i = Some b
                 /\ snd a = b /\ (i < length bs)%nat.
Proof.
  intros sp bs a Ha. unfold string_stores in Ha. destruct Ha as [<-|Ha]; [left; auto|right].
  apply in_map_iff in Ha. destruct Ha as ([j b] & <- & Hj). apply In_combine_zrange in Hj.
  destruct Hj as [Hj Hb]. exists (Z.to_nat j), b. simpl. rewrite Z2Nat.id by lia.
  repeat split; auto. apply nth_error_Some. congruence.
Qed.

Lemma string_stores_len:
  forall sp bs, In (sp ++ [PField "len"], Puint32, Z.of_nat (length bs)) (string_stores sp bs).
Proof. intros; left; auto. Qed.

Lemma string_stores_data:
  forall sp bs i b, nth_error bs i = Some b ->
  In (sp ++ [PField "data"; PIndex (Z.of_nat i)], Puint8, b) (string_stores sp bs).
Proof.
  intros sp bs i b H. right. apply in_map_iff. exists (Z.of_nat i, b). split; auto.
  apply In_combine_zrange. rewrite Nat2Z.id. split; auto.
  assert (i < length bs)%nat by (apply nth_error_Some; congruence). lia.
Qed.

(** Two stores of strings at one path are stores of one string. *)
Lemma string_store_path_inj:
  forall sp1 bs1 sp2 bs2 a1 a2,
  In a1 (string_stores sp1 bs1) -> In a2 (string_stores sp2 bs2) ->
  fst (fst a1) = fst (fst a2) -> sp1 = sp2.
Proof.
  intros sp1 bs1 sp2 bs2 a1 a2 H1 H2 E.
  destruct (string_stores_path _ _ _ H1) as [[E1 _]|(i & b & E1 & _)];
  destruct (string_stores_path _ _ _ H2) as [[E2 _]|(j & c & E2 & _)];
  rewrite E1, E2 in E.
  - apply app_inj_tail in E. tauto.
  - replace [PField "data"; PIndex (Z.of_nat j)] with ([PField "data"] ++ [PIndex (Z.of_nat j)]) in E by reflexivity.
    rewrite app_assoc in E. apply app_inj_tail in E. destruct E as [_ E]; discriminate.
  - replace [PField "data"; PIndex (Z.of_nat i)] with ([PField "data"] ++ [PIndex (Z.of_nat i)]) in E by reflexivity.
    rewrite app_assoc in E. apply app_inj_tail in E. destruct E as [_ E]; discriminate.
  - replace [PField "data"; PIndex (Z.of_nat i)] with ([PField "data"] ++ [PIndex (Z.of_nat i)]) in E by reflexivity.
    replace [PField "data"; PIndex (Z.of_nat j)] with ([PField "data"] ++ [PIndex (Z.of_nat j)]) in E by reflexivity.
    rewrite !app_assoc in E. apply app_inj_tail in E. destruct E as [E _].
    apply app_inj_tail in E. tauto.
Qed.

Lemma string_stores_nodup:
  forall sp bs, NoDup (map (fun a => fst (fst a)) (string_stores sp bs)).
Proof.
  intros sp bs. unfold string_stores. cbn [map fst]. constructor.
  - rewrite map_map. intros H. apply in_map_iff in H. destruct H as ([j b] & E & _). simpl in E.
    replace [PField "data"; PIndex j] with ([PField "data"] ++ [PIndex j]) in E by reflexivity.
    rewrite app_assoc in E. apply app_inj_tail in E. destruct E as [_ E]; discriminate.
  - rewrite map_map.
    assert (Hf: forall (l1 l2 : list Z), NoDup l1 ->
                NoDup (map (fun x : Z * Z => sp ++ [PField "data"; PIndex (fst x)]) (combine l1 l2))).
    { induction l1 as [|x l1 IH]; intros [|y l2] N; simpl; [constructor|constructor|constructor|].
      inversion N as [|? ? Hn N']; subst. constructor; [|apply IH; auto].
      intros H. apply in_map_iff in H. destruct H as ([x' y'] & E & Hin). simpl in E.
      apply app_inv_head in E. inversion E; subst x'. apply in_combine_l in Hin. contradiction. }
    exact (Hf _ bs (NoDup_map_inv _ _ (NoDup_zrange _))).
Qed.

Lemma In_topic_stores:
  forall m c a, In a (topic_stores m c) <->
  exists sp bs, In (c, (sp, bs)) (nm_strings m) /\ In a (string_stores sp bs).
Proof.
  intros m c a. unfold topic_stores. rewrite in_flat_map. split.
  - intros ([sp bs] & H & Ha). exists sp, bs. split; auto. apply In_topic_strings; auto.
  - intros (sp & bs & H & Ha). exists (sp, bs). split; auto. apply In_topic_strings; auto.
Qed.

(** A topic's stores of constant strings write each path once. *)
Lemma topic_stores_nodup:
  forall m c, wf_facts m -> NoDup (map (fun a => fst (fst a)) (topic_stores m c)).
Proof.
  intros m c W. unfold topic_stores, topic_strings.
  assert (ND: NoDup (map string_target (filter (fun st => ident_eqb (fst st) c) (nm_strings m)))).
  { generalize (wf_strings_nodup m W). generalize (nm_strings m). induction l as [|x l IH]; simpl; auto.
    intros N. inversion N as [|? ? Hn N']; subst. destruct (ident_eqb (fst x) c); simpl; auto.
    constructor; auto. intros H. apply Hn. apply in_map_iff in H. destruct H as (y & E & Hy).
    apply filter_In in Hy. apply in_map_iff. exists y; tauto. }
  assert (Hc: forall st, In st (filter (fun st => ident_eqb (fst st) c) (nm_strings m)) -> fst st = c).
  { intros st H. apply filter_In in H. apply ident_eqb_true; tauto. }
  generalize dependent (filter (fun st => ident_eqb (fst st) c) (nm_strings m)).
  induction l as [|[c' [sp bs]] l IH]; intros ND Hc; cbn [map flat_map fst snd]; [constructor|].
  inversion ND as [|? ? Hn ND']; subst. rewrite map_app. apply NoDup_app_intro.
  - apply string_stores_nodup.
  - apply IH; auto. intros st H; apply Hc; simpl; auto.
  - intros x H1 H2. apply in_map_iff in H1. destruct H1 as (a1 & E1 & H1).
    apply in_map_iff in H2. destruct H2 as (a2 & E2 & H2).
    apply in_flat_map in H2. destruct H2 as ([sp2 bs2] & H2 & Ha2).
    apply in_map_iff in H2. destruct H2 as ([c2 [sp3 bs3]] & E3 & H3). simpl in E3. inversion E3; subst sp3 bs3.
    assert (Esp: sp = sp2) by (apply (string_store_path_inj sp bs sp2 bs2 a1 a2); auto; congruence).
    subst sp2. apply Hn. apply in_map_iff. exists (c2, (sp, bs2)). split; auto.
    unfold string_target; simpl. f_equal.
    transitivity c; [apply (Hc (c2, (sp, bs2))); simpl; auto|symmetry; apply (Hc (c', (sp, bs))); simpl; auto].
Qed.
