(** * Symbolic execution of the generated copies *)

(** The facts that the proofs of T1 ([Glueproof]) and T2 ([Loopproof])
    share:
    - on memory values: shapes ([mval_shape]), and the extensionality of
      well-typed values: two values of the same shape whose scalar leaves
      agree are equal ([typed_ext]);
    - on the node model: its structs are well formed ([wf_composites_of]),
      the C type at a model path is the C type of the model type it
      resolves to ([type_at_ctype]), the scalar leaves of a message are
      its model leaves ([scalar_is_leaf]), distinct leaves are disjoint
      ([leaves_disjoint]);
    - on the semantics: the generated access [e.p] designates the
      location of [e] followed by [p] ([eval_lvalue_path]), and the copy
      template [tmp = src; dst = tmp;] stores the value of [src] at [dst]
      ([exec_copy]). *)

From Coq Require Import String List ZArith Bool Lia.
From ROSGen Require Import Errors Maps Syntax Values Memory Environment Semantics NodeModel Wellformed Generator Generatorspec Generatorproof DDC.
Import ListNotations.

Local Open Scope list_scope.

(** ** Generic facts on values *)

Notation shape_field := (fun fv : ident * mval => (fst fv, mval_shape (snd fv))).

Lemma mval_shape_struct:
  forall fs, mval_shape (MVstruct fs) = MVstruct (map shape_field fs).
Proof. reflexivity. Qed.

Lemma find_assoc_shape:
  forall f fs, find_assoc f (map shape_field fs) = option_map mval_shape (find_assoc f fs).
Proof.
  induction fs as [|[g v] fs IH]; simpl; auto. destruct (string_dec f g); auto.
Qed.

(** Reading the shape of a value is taking the shape of what one reads. *)
Lemma mval_get_shape:
  forall p v, mval_get (mval_shape v) p = option_map mval_shape (mval_get v p).
Proof.
  induction p as [|s p IH]; intros v; simpl; auto.
  destruct s as [f|i], v as [x|fs|es]; simpl; auto.
  - rewrite (find_assoc_shape f fs). destruct (find_assoc f fs); simpl; auto.
  - destruct (Z.leb 0 i); auto. rewrite nth_error_map.
    destruct (nth_error es (Z.to_nat i)); simpl; auto.
Qed.

Lemma mval_get_same_shape:
  forall v1 v2 p x1, mval_shape v1 = mval_shape v2 -> mval_get v1 p = Some x1 ->
  exists x2, mval_get v2 p = Some x2 /\ mval_shape x2 = mval_shape x1.
Proof.
  intros v1 v2 p x1 E G.
  assert (H: option_map mval_shape (mval_get v2 p) = Some (mval_shape x1)).
  { rewrite <- mval_get_shape, <- E, mval_get_shape, G. reflexivity. }
  destruct (mval_get v2 p) as [x2|]; simpl in H; inversion H; eauto.
Qed.

(** Values of the same type have the same shape. *)
Lemma mval_shape_typed:
  forall ce v1 ty v2, mval_has_type ce ty v1 -> mval_has_type ce ty v2 ->
  mval_shape v1 = mval_shape v2.
Proof.
  intros ce v1; induction v1 as [x | fs IH | es IH] using mval_ind2; intros ty v2 H1 H2.
  - inversion H1; subst. inversion H2; subst; auto.
    all: match goal with H : is_scalar_type _ = true |- _ => discriminate H end.
  - inversion H1 as [| id members fs1 SM F1 |]; subst.
    inversion H2 as [ty' x Hs _ | id' members' fs2 SM' F2 | ]; subst; [discriminate Hs|].
    rewrite SM in SM'; inversion SM'; subst members'. clear SM SM' H1 H2.
    simpl; f_equal. revert members fs2 F1 F2.
    induction IH as [|[f v] fs' Hv IHfs IHrec]; intros members fs2 F1 F2;
      inversion F1 as [| f1 t1 mv1 ms1 fs1' T1 R1]; subst;
      inversion F2 as [| f2 t2 mv2 ms2 fs2' T2 R2]; subst; simpl; auto.
    simpl in Hv. rewrite (Hv _ mv2) by eauto. f_equal. eapply IHrec; eauto.
  - inversion H1 as [| | t n es1 L1 E1]; subst.
    inversion H2 as [ty' x Hs _ | | t' n' es2 L2 E2]; subst; [discriminate Hs|].
    simpl; f_equal. assert (Len: length es = length es2) by lia. clear H1 H2 L2.
    revert es2 E1 E2 Len.
    induction IH as [|v es' Hv IHes IHrec]; intros es2 E1 E2 Len;
      destruct es2 as [|w es2]; simpl in Len; try discriminate; auto.
    inversion E1; subst; inversion E2; subst. simpl.
    rewrite (Hv _ w) by eauto. f_equal. eapply IHrec; eauto.
Qed.

(** The shape of a default value is the uninitialised value. *)
Lemma default_of_ext_fun:
  forall dflt zs1 zs2 ty, (forall id, zs1 id = zs2 id) ->
  default_of dflt zs1 ty = default_of dflt zs2 ty.
Proof.
  intros dflt zs1 zs2 ty H; induction ty; simpl; auto. rewrite IHty; auto.
Qed.

Lemma map_repeat_eq:
  forall (A B : Type) (f : A -> B) x n, map f (repeat x n) = repeat (f x) n.
Proof. induction n; simpl; f_equal; auto. Qed.

Lemma shape_default_of:
  forall dflt zs ty,
  mval_shape (default_of dflt zs ty) = default_of (fun _ => Vundef) (fun id => mval_shape (zs id)) ty.
Proof.
  intros dflt zs ty; induction ty; simpl; auto.
  rewrite map_repeat_eq, IHty; auto.
Qed.

Lemma shape_struct_default:
  forall dflt rce id, mval_shape (struct_default dflt rce id) = struct_default (fun _ => Vundef) rce id.
Proof.
  induction rce as [|co rce IH]; intros id; simpl; auto.
  destruct (ident_eq (co_name co) id); auto.
  simpl. f_equal. rewrite map_map. apply map_ext. intros [f t]; simpl. f_equal.
  rewrite shape_default_of. apply default_of_ext_fun. auto.
Qed.

Lemma shape_default_mval:
  forall dflt ce ty, mval_shape (default_mval dflt ce ty) = undef_mval ce ty.
Proof.
  intros dflt ce ty. unfold default_mval, undef_mval, default_mval.
  rewrite shape_default_of. apply default_of_ext_fun. intros; apply shape_struct_default.
Qed.

Lemma shape_zero_mval: forall ce ty, mval_shape (zero_mval ce ty) = undef_mval ce ty.
Proof. intros; apply shape_default_mval. Qed.

Lemma shape_undef_mval: forall ce ty, mval_shape (undef_mval ce ty) = undef_mval ce ty.
Proof. intros; apply shape_default_mval. Qed.

(** Replacing a sub-value by one of the same shape keeps the shape. *)
Lemma shape_set_field:
  forall f x fs y, find_assoc f fs = Some y -> mval_shape x = mval_shape y ->
  map shape_field (set_field f x fs) = map shape_field fs.
Proof.
  induction fs as [|[g v] fs IH]; simpl; intros y F E; try discriminate.
  destruct (string_dec f g) as [e|n]; destruct (ident_eq f g); try congruence.
  - inversion F; subst. simpl. simpl. rewrite E; auto.
  - simpl. f_equal; eauto.
Qed.

Lemma shape_replace_nth:
  forall es k x y, nth_error es k = Some y -> mval_shape x = mval_shape y ->
  map mval_shape (replace_nth es k x) = map mval_shape es.
Proof.
  induction es as [|v es IH]; destruct k; simpl; intros x y F E; try discriminate.
  - inversion F; subst; rewrite E; auto.
  - f_equal; eauto.
Qed.

Lemma mval_shape_set:
  forall p v x v' y, mval_get v p = Some y -> mval_shape x = mval_shape y ->
  mval_set v p x = Some v' -> mval_shape v' = mval_shape v.
Proof.
  induction p as [|s p IH]; simpl; intros v x v' y G E S.
  - inversion G; inversion S; subst; auto.
  - destruct (get_step v s) as [z|] eqn:GS; try discriminate.
    destruct (mval_set z p x) as [z'|] eqn:S'; try discriminate.
    assert (Ez: mval_shape z' = mval_shape z) by eauto.
    destruct s as [f|i], v as [w|fs|es]; simpl in GS, S; try discriminate.
    + rewrite GS in S. inversion S; subst. simpl. f_equal. eapply shape_set_field; eauto.
    + destruct (Z.leb 0 i); try discriminate. simpl in S.
      destruct (Nat.ltb (Z.to_nat i) (length es)); inversion S; subst.
      simpl. f_equal. eapply shape_replace_nth; eauto.
Qed.

(** Reading a typed value: the sub-value has the type at the path. *)
Lemma fields_have_type_find_rev:
  forall ce members fs f x, fields_have_type ce members fs -> find_assoc f fs = Some x ->
  exists t, find_assoc f members = Some t /\ mval_has_type ce t x.
Proof.
  intros ce members fs f x H; induction H as [|g tg mv ms fs' Hmv Hfs IH]; simpl; intros E;
    try discriminate.
  destruct (string_dec f g); [inversion E; subst; eauto | auto].
Qed.

Lemma elems_have_type_nth_rev:
  forall ce t es k x, elems_have_type ce t es -> nth_error es k = Some x -> mval_has_type ce t x.
Proof.
  intros ce t es k x H; revert k; induction H as [|t' mv es' Hmv Hes IH]; intros k E;
    destruct k; simpl in E; try discriminate; [inversion E; subst; auto | eauto].
Qed.

Lemma mval_get_typed_inv:
  forall ce p ty v x, mval_has_type ce ty v -> mval_get v p = Some x ->
  exists t, type_at ce ty p = Some t /\ mval_has_type ce t x.
Proof.
  induction p as [|s p IH]; simpl; intros ty v x H G.
  - inversion G; subst; eauto.
  - destruct (get_step v s) as [y|] eqn:GS; try discriminate.
    assert (T: exists t1, type_step ce ty s = Some t1 /\ mval_has_type ce t1 y).
    { inversion H as [ty' w Hs Hw | id members fs SM F | t n es L E]; subst;
        destruct s as [f|i]; simpl in GS; try discriminate.
      - simpl. rewrite SM. eapply fields_have_type_find_rev; eauto.
      - simpl. destruct (Z.leb 0 i) eqn:Hi; try discriminate.
        assert (Hl: (Z.to_nat i < length es)%nat) by (apply nth_error_Some; congruence).
        apply Z.leb_le in Hi.
        replace (Z.ltb i (Z.of_nat (length es))) with true by (symmetry; apply Z.ltb_lt; lia).
        eexists; split; [reflexivity|]. eapply elems_have_type_nth_rev; eauto. }
    destruct T as [t1 [T1 Ht1]]. rewrite T1. eapply IH; eauto.
Qed.

(** The member names of a struct of a well-formed environment are
    distinct. *)
Lemma struct_members_nodup:
  forall ce id members, wf_composites ce -> struct_members ce id = Some members ->
  NoDup (map fst members).
Proof.
  intros ce id members WF SM. unfold struct_members in SM.
  destruct (find_composite id ce) as [co|] eqn:FC; inversion SM; subst.
  destruct (find_composite_split _ _ _ FC) as [_ [pre [post [E _]]]].
  destruct (composites_ok_inv ce [] WF) as [_ [_ MEM]].
  apply (MEM pre co post E).
Qed.

Lemma fields_have_type_names:
  forall ce members fs, fields_have_type ce members fs -> map fst fs = map fst members.
Proof. induction 1; simpl; f_equal; auto. Qed.

Lemma find_assoc_notin:
  forall (A : Type) f (l : list (ident * A)), ~ In f (map fst l) -> find_assoc f l = None.
Proof.
  induction l as [|[g a] l IH]; simpl; intros H; auto.
  destruct (string_dec f g); [subst; tauto | auto].
Qed.

(** Extensionality: a well-typed value [v1] is equal to any value [v2] of
    the same shape that has the same scalar at every path where [v1] has
    a scalar. *)
Lemma typed_ext:
  forall ce, wf_composites ce ->
  forall v1 ty v2, mval_has_type ce ty v1 -> mval_shape v2 = mval_shape v1 ->
  (forall p x, mval_get v1 p = Some (MVscalar x) -> mval_get v2 p = Some (MVscalar x)) ->
  v2 = v1.
Proof.
  intros ce WF v1; induction v1 as [x | fs IH | es IH] using mval_ind2; intros ty v2 H1 E L.
  - generalize (L [] x eq_refl); simpl; congruence.
  - inversion H1 as [| id members fs1 SM F1 |]; subst.
    destruct v2 as [w|fs2|es2]; simpl in E; try discriminate. injection E; clear E; intros E'.
    assert (ND: NoDup (map fst fs)).
    { rewrite (fields_have_type_names _ _ _ F1). eapply struct_members_nodup; eauto. }
    f_equal. clear H1 SM.
    revert members fs2 F1 E' L ND.
    induction IH as [|[f v] fs' Hv IHfs IHrec]; intros members fs2 F1 E' L ND;
      destruct fs2 as [|[g w] fs2']; simpl in E'; try discriminate; auto.
    injection E'; intros Etl Ehd Ename. simpl in *. subst g.
    inversion F1 as [| f1 t1 mv1 ms1 fs1' T1 R1]; subst.
    inversion ND as [| ? ? Hnin ND']; subst.
    assert (Ev: w = v).
    { eapply Hv; eauto. intros p x G.
      generalize (L (Sfield f :: p) x); simpl.
      destruct (string_dec f f) as [_|C]; [|congruence]. auto. }
    subst w. f_equal. eapply IHrec; eauto.
    intros p x G. destruct p as [|[g|i] p]; simpl in G; try discriminate.
    destruct (find_assoc g fs') as [y|] eqn:Fg; try discriminate.
    destruct (string_dec g f) as [e|n].
    + subst g. rewrite find_assoc_notin in Fg; [discriminate | auto].
    + generalize (L (Sfield g :: p) x); simpl.
      destruct (string_dec g f) as [e'|_]; [congruence|]. rewrite Fg. auto.
  - inversion H1 as [| | t n es1 Len E1]; subst.
    destruct v2 as [w|fs2|es2]; simpl in E; try discriminate. injection E; clear E; intros E'.
    f_equal. clear H1.
    revert es2 E1 E' L.
    induction IH as [|v es' Hv IHes IHrec]; intros es2 E1 E' L;
      destruct es2 as [|w es2']; simpl in E'; try discriminate; auto.
    injection E'; intros Etl Ehd.
    inversion E1 as [| t' mv es'' Tv Tes]; subst.
    assert (Ev: w = v).
    { eapply Hv; eauto. intros p x G. generalize (L (Sindex 0 :: p) x); simpl; auto. }
    subst w. f_equal. eapply IHrec; eauto.
    intros p x G. destruct p as [|[g|i] p]; simpl in G; try discriminate.
    destruct (Z.leb 0 i) eqn:Hi; try discriminate.
    generalize (L (Sindex (i + 1) :: p) x); simpl.
    apply Z.leb_le in Hi.
    replace (Z.leb 0 (i + 1)) with true by (symmetry; apply Z.leb_le; lia).
    replace (Z.to_nat (i + 1)) with (S (Z.to_nat i)) by lia. simpl.
    replace (Z.leb 0 i) with true by (symmetry; apply Z.leb_le; lia). auto.
Qed.

(** ** Paths *)

Lemma path_steps_app:
  forall p q, path_steps (p ++ q) = path_steps p ++ path_steps q.
Proof. intros; unfold path_steps; apply map_app. Qed.

Definition pstep_of_step (s : step) : pstep :=
  match s with Sfield f => PField f | Sindex i => PIndex i end.

Lemma path_steps_surj: forall p, path_steps (map pstep_of_step p) = p.
Proof.
  intros p; unfold path_steps; rewrite map_map.
  induction p as [|[f|i] p IH]; simpl; f_equal; auto.
Qed.

Lemma step_of_pstep_inj: forall s1 s2, step_of_pstep s1 = step_of_pstep s2 -> s1 = s2.
Proof. intros [f|i] [g|j]; simpl; intros E; inversion E; auto. Qed.

Lemma pstep_eq_dec: forall s1 s2 : pstep, {s1 = s2} + {s1 <> s2}.
Proof. decide equality; [apply string_dec | apply Z.eq_dec]. Defined.

(** ** The node model's types *)

Section MODEL.

Variable m : node_model.
Hypothesis W : wf_facts m.

Local Notation msgs := (nm_msgs m).
Local Notation ce := (composites m).

Lemma in_ident_existsb:
  forall x l, in_ident x l = existsb (ident_eqb x) l.
Proof.
  intros x l; unfold in_ident. induction l as [|y l IH]; simpl; auto.
  rewrite IH. f_equal. destruct (ident_eq y x) as [e|n].
  - subst; rewrite ident_eqb_refl; auto.
  - symmetry; apply ident_eqb_false; auto.
Qed.

Lemma ftype_ok_complete:
  forall seen t, ftype_ok seen t = true -> complete_type seen (ctype_of_ftype t) = true.
Proof.
  induction t as [q|id|t IH n]; simpl; intros H.
  - destruct q; reflexivity.
  - rewrite in_ident_existsb; auto.
  - rewrite !andb_true_iff in H. destruct H as [[H1 _] H3].
    rewrite andb_true_iff; split; auto. apply Z.leb_le. apply Z.ltb_lt in H1. lia.
Qed.

Lemma composites_ok_msgs:
  forall l known rest,
  msgs_ok known l = true ->
  NoDup (md_names l) -> (forall x, In x (md_names l) -> ~ In x known) ->
  (forall md, In md l -> NoDup (map fst (md_fields md))) ->
  composites_ok (rev (md_names l) ++ known) rest = true ->
  composites_ok known (map composite_of_msgdef l ++ rest) = true.
Proof.
  induction l as [|md l IH]; simpl; intros known rest OK ND D NF R; auto.
  apply andb_true_iff in OK; destruct OK as [OKmd OKl].
  inversion ND as [|? ? Hn ND']; subst.
  unfold msgdef_ok in OKmd. rewrite !andb_true_iff in OKmd.
  destruct OKmd as [_ Hft].
  rewrite !andb_true_iff; split; [split; [split|]|].
  - apply negb_true_iff. destruct (in_ident (md_name md) known) eqn:E; auto.
    apply in_ident_spec in E. elim (D (md_name md)); auto.
  - apply nodup_idents_spec. simpl. rewrite map_map; simpl. apply NF; auto.
  - rewrite forallb_forall. intros [f t] Hin. simpl in Hin.
    apply in_map_iff in Hin. destruct Hin as ([f' t'] & E & Hin). inversion E; subst.
    simpl. apply ftype_ok_complete. rewrite forallb_forall in Hft. apply (Hft _ Hin).
  - apply IH; auto.
    + intros x Hx [Hx'|Hx']; [subst; contradiction|]. apply (D x); auto.
    + rewrite <- app_assoc in R. exact R.
Qed.

Lemma scope_ok_field_names:
  forall s, scope_ok s -> forall md, In md s -> NoDup (map fst (md_fields md)).
Proof. induction 1 as [|md0 rest _ ND _ _ IH]; simpl; intros md H; [contradiction|]. destruct H as [<-|H]; auto. Qed.

Lemma msg_names_nodup: NoDup (md_names msgs).
Proof. apply wf_msg_names_nodup; auto. Qed.

(** The structs of a well-formed model are well formed. *)
Lemma wf_composites_of: wf_composites ce.
Proof.
  unfold wf_composites, composites.
  apply composites_ok_msgs.
  - apply wf_msgs; auto.
  - apply msg_names_nodup.
  - simpl; tauto.
  - intros md H. apply (scope_ok_field_names _ (wf_scope_ok m W)). apply -> in_rev; auto.
  - rewrite app_nil_r. simpl.
    assert (N1: ~ In (nm_in_struct m) (md_names msgs)) by (apply in_struct_not_msg; auto).
    assert (N2: ~ In (nm_out_struct m) (md_names msgs)) by (apply out_struct_not_msg; auto).
    assert (N3: nm_in_struct m <> nm_out_struct m) by (apply in_out_structs_differ; auto).
    assert (Cp: forall known (l : list (ident * ftype)),
              (forall xt, In xt l -> ctrl_ftype_ok (snd xt) = true) ->
              forallb (fun mt : ident * type => complete_type known (snd mt))
                      (map (fun xt : ident * ftype => (fst xt, ctype_of_ftype (snd xt))) l) = true).
    { intros known l OKl. rewrite forallb_forall. intros x Hx.
      apply in_map_iff in Hx; destruct Hx as ([y t] & <- & Hin). simpl.
      generalize (OKl _ Hin); simpl. destruct t as [q| |[q| |] n]; simpl; try discriminate.
      - destruct q; reflexivity.
      - intros H. rewrite andb_true_iff in H; destruct H as [H1 _]. apply Z.ltb_lt in H1.
        assert (Hn: (0 <=? n)%Z = true) by (apply Z.leb_le; lia).
        destruct q; simpl; rewrite ?Hn; reflexivity. }
    assert (Nd: forall l : list (ident * ftype), NoDup (map fst l) ->
              nodup_idents (map fst (map (fun xt => (fst xt, ctype_of_ftype (snd xt))) l)) = true).
    { intros l H. apply nodup_idents_spec. rewrite map_map; simpl; auto. }
    rewrite !Cp by (first [apply wf_inputs_ok | apply wf_outputs_ok]; auto).
    rewrite !Nd by (first [apply wf_inputs_nodup | apply wf_outputs_nodup]; auto).
    destruct (in_ident (nm_in_struct m) (rev (md_names (nm_msgs m)))) eqn:E1.
    { apply in_ident_spec, in_rev in E1. contradiction. }
    destruct (ident_eq (nm_in_struct m) (nm_out_struct m)); [contradiction|].
    destruct (in_ident (nm_out_struct m) (rev (md_names (nm_msgs m)))) eqn:E2.
    { apply in_ident_spec, in_rev in E2. contradiction. }
    reflexivity.
Qed.

(** Field types of the model's messages refer to the model's messages. *)
Lemma fields_ok:
  forall md f t, In md msgs -> In (f, t) (md_fields md) -> ftype_ok (md_names msgs) t = true.
Proof.
  intros md f t Hmd Hf.
  apply ftype_ok_incl with (md_names (rev msgs)).
  - intros x; unfold md_names; rewrite map_rev, <- in_rev; auto.
  - apply (scope_ok_fields _ (wf_scope_ok m W) md f t); auto. apply -> in_rev; auto.
Qed.

Lemma find_msg_exists:
  forall id, In id (md_names msgs) -> exists md, find_msg msgs id = Some md.
Proof.
  intros id H. destruct (find_msg msgs id) as [md|] eqn:F; eauto.
  apply find_msg_None in F. contradiction.
Qed.

Lemma struct_members_msg:
  forall id md, find_msg msgs id = Some md ->
  struct_members ce id = Some (map (fun ft => (fst ft, ctype_of_ftype (snd ft))) (md_fields md)).
Proof.
  intros id md F. unfold struct_members, composites.
  rewrite (find_composite_msgs _ _ _ _ F). reflexivity.
Qed.

Lemma field_type_msg:
  forall id md f, find_msg msgs id = Some md ->
  Generator.field_type ce id f = option_map ctype_of_ftype (find_assoc f (md_fields md)).
Proof.
  intros id md f F. unfold Generator.field_type, composites.
  rewrite (find_composite_msgs _ _ _ _ F). simpl. apply find_assoc_map_ctype.
Qed.

(** The C type at a model path is the C type of what the path resolves to. *)
Lemma type_at_ctype:
  forall p t, ftype_ok (md_names msgs) t = true ->
  type_at ce (ctype_of_ftype t) (path_steps p) = option_map ctype_of_ftype (resolve msgs t p).
Proof.
  induction p as [|[f|i] p IH]; intros t Ht; [reflexivity| |].
  - destruct t as [q|id|t n].
    + destruct q; reflexivity.
    + apply ftype_ok_msg in Ht. destruct (find_msg_exists id Ht) as [md F].
      assert (TS: type_step ce (Tstruct id) (Sfield f)
                  = option_map ctype_of_ftype (find_assoc f (md_fields md))).
      { simpl. rewrite (struct_members_msg id md F). unfold Values.field_type.
        apply find_assoc_map_ctype. }
      assert (R: resolve msgs (FTmsg id) (PField f :: p)
                 = match find_assoc f (md_fields md) with
                   | Some t' => resolve msgs t' p | None => None end)
        by (simpl; rewrite F; reflexivity).
      assert (T: type_at ce (ctype_of_ftype (FTmsg id)) (path_steps (PField f :: p))
                 = match type_step ce (Tstruct id) (Sfield f) with
                   | Some t => type_at ce t (path_steps p) | None => None end) by reflexivity.
      rewrite R, T, TS.
      destruct (find_assoc f (md_fields md)) as [tf|] eqn:Ff; simpl; auto.
      apply IH. apply find_assoc_In in Ff. apply find_msg_In in F.
      eapply fields_ok; [apply F | eauto].
    + reflexivity.
  - destruct t as [q|id|t n].
    + destruct q; reflexivity.
    + reflexivity.
    + simpl. simpl in Ht. rewrite !andb_true_iff in Ht. 
      destruct (Z.leb 0 i && Z.ltb i n)%bool; auto. apply IH; tauto.
Qed.

Lemma ctype_scalar_prim:
  forall t, is_scalar_type (ctype_of_ftype t) = true -> exists q, t = FTprim q.
Proof. intros [q|id|t n]; simpl; intros H; try discriminate; eauto. Qed.

Lemma resolve_leaf_msg:
  forall M p q, resolve msgs (FTmsg M) p = Some (FTprim q) -> In M (md_names msgs).
Proof.
  intros M p q H. destruct p as [|[f|i] p]; simpl in H; try discriminate.
  destruct (find_msg msgs M) as [md|] eqn:F; try discriminate.
  apply find_msg_In in F. destruct F as [F <-]. apply in_map; auto.
Qed.

(** A leaf of the message type holds a scalar of the leaf's C type. *)
Lemma leaf_typed:
  forall M p q v, resolve msgs (FTmsg M) p = Some (FTprim q) ->
  mval_has_type ce (Tstruct M) v ->
  exists x, mval_get v (path_steps p) = Some (MVscalar x) /\ val_has_type x (ctype_of_prim q).
Proof.
  intros M p q v R H.
  assert (T: type_at ce (ctype_of_ftype (FTmsg M)) (path_steps p) = Some (ctype_of_prim q)).
  { rewrite type_at_ctype. rewrite R; auto. apply ftype_ok_msg. eapply resolve_leaf_msg; eauto. }
  destruct (mval_get_has_type _ _ _ _ _ H T) as [x [G Hx]].
  inversion Hx; subst; eauto; destruct q; discriminate.
Qed.

(** The scalars of a value of a message type are at its leaves. *)
Lemma scalar_is_leaf:
  forall M v p x, In M (md_names msgs) -> mval_has_type ce (Tstruct M) v ->
  mval_get v p = Some (MVscalar x) ->
  exists lp q, p = path_steps lp /\ resolve msgs (FTmsg M) lp = Some (FTprim q).
Proof.
  intros M v p x HM H G.
  destruct (mval_get_typed_inv _ _ _ _ _ H G) as [t [T Hx]].
  rewrite <- (path_steps_surj p) in T.
  change (Tstruct M) with (ctype_of_ftype (FTmsg M)) in T.
  rewrite type_at_ctype in T by (apply ftype_ok_msg; auto).
  destruct (resolve msgs (FTmsg M) (map pstep_of_step p)) as [ft|] eqn:R; simpl in T; try discriminate.
  inversion T; subst t.
  assert (S: is_scalar_type (ctype_of_ftype ft) = true) by (inversion Hx; auto).
  destruct (ctype_scalar_prim ft S) as [q ->].
  exists (map pstep_of_step p), q. rewrite path_steps_surj; auto.
Qed.

(** Two values of a message type, of the same shape, that agree on all
    leaves of the message are equal. *)
Lemma leaves_ext:
  forall M v1 v2, In M (md_names msgs) ->
  mval_has_type ce (Tstruct M) v1 -> mval_shape v2 = mval_shape v1 ->
  (forall lp q, resolve msgs (FTmsg M) lp = Some (FTprim q) ->
     mval_get v2 (path_steps lp) = mval_get v1 (path_steps lp)) ->
  v2 = v1.
Proof.
  intros M v1 v2 HM H1 E L.
  apply (typed_ext ce wf_composites_of v1 (Tstruct M) v2 H1 E).
  intros p x G. destruct (scalar_is_leaf M v1 p x HM H1 G) as (lp & q & -> & R).
  rewrite (L lp q R); auto.
Qed.

(** Resolution one step at a time. *)
Definition rstep (t : ftype) (s : pstep) : option ftype :=
  match s, t with
  | PField f, FTmsg id =>
      match find_msg msgs id with
      | Some md => find_assoc f (md_fields md)
      | None => None
      end
  | PIndex i, FTarray t' n => if ((0 <=? i)%Z && (i <? n)%Z)%bool then Some t' else None
  | _, _ => None
  end.

Lemma resolve_step_eq:
  forall t s p, resolve msgs t (s :: p) =
  match rstep t s with Some t' => resolve msgs t' p | None => None end.
Proof.
  intros t [f|i] p; destruct t as [q|id|t n]; simpl; auto.
  all: try (destruct (find_msg msgs id) as [md|]; auto; destruct (find_assoc f (md_fields md)); auto).
  all: try (destruct ((0 <=? i)%Z && (i <? n)%Z); auto).
Qed.

Lemma resolve_prim_cons:
  forall q s p, resolve msgs (FTprim q) (s :: p) = None.
Proof. intros q [f|i] p; reflexivity. Qed.

(** Distinct leaves designate disjoint sub-values. *)
Lemma leaves_disjoint:
  forall p1 p2 t q1 q2, resolve msgs t p1 = Some (FTprim q1) -> resolve msgs t p2 = Some (FTprim q2) ->
  p1 <> p2 -> path_disjoint (path_steps p1) (path_steps p2).
Proof.
  induction p1 as [|s1 p1 IH]; intros p2 t q1 q2 R1 R2 N.
  - simpl in R1. inversion R1; subst t.
    destruct p2 as [|s2 p2]; [congruence|]. rewrite resolve_prim_cons in R2; discriminate.
  - destruct p2 as [|s2 p2].
    + simpl in R2. inversion R2; subst t. rewrite resolve_prim_cons in R1; discriminate.
    + simpl. destruct (pstep_eq_dec s1 s2) as [E|E].
      * subst s2. right. rewrite resolve_step_eq in R1, R2.
        destruct (rstep t s1) as [t'|]; try discriminate.
        apply (IH p2 t' q1 q2); auto. congruence.
      * left. intros E'. apply step_of_pstep_inj in E'. contradiction.
Qed.

(** ** Evaluation of the generated accesses *)

(** An array index of a well-formed model is an [int] constant that
    evaluates to itself. *)
Lemma norm_int_index: forall i, (0 <= i <= max_array)%Z -> norm_int I32 Signed i = i.
Proof.
  intros i H. unfold max_array in H. unfold norm_int, wrap, wrap_signed, bitsize.
  change (2 ^ 32)%Z with 4294967296%Z. change (2 ^ (32 - 1))%Z with 2147483648%Z.
  rewrite Z.mod_small by lia.
  replace (i <? 2147483648)%Z with true by (symmetry; apply Z.ltb_lt; lia). reflexivity.
Qed.

(** [e.p], for a model path [p] from the type of [e], designates the
    location of [e] followed by [p]. *)
Lemma eval_lvalue_path:
  forall ge e le mm p t t' ex b q0,
  ftype_ok (md_names msgs) t = true -> resolve msgs t p = Some t' ->
  typeof ex = ctype_of_ftype t -> eval_lvalue ge e le mm ex = Some (b, q0) ->
  eval_lvalue ge e le mm (path_expr ce ex p) = Some (b, q0 ++ path_steps p)
  /\ typeof (path_expr ce ex p) = ctype_of_ftype t'.
Proof.
  intros ge e le mm p; induction p as [|[f|i] p IH]; intros t t' ex b q0 Ht R T E.
  - simpl in R. inversion R; subst. simpl. rewrite app_nil_r. auto.
  - destruct t as [q|id|tf n]; simpl in R; try discriminate.
    destruct (find_msg msgs id) as [md|] eqn:F; try discriminate.
    destruct (find_assoc f (md_fields md)) as [tf|] eqn:Ff; try discriminate.
    assert (SE: step_expr ce ex (PField f) = Efield ex f (ctype_of_ftype tf)).
    { unfold step_expr, step_type. rewrite T. simpl. 
      rewrite (field_type_msg id md f F), Ff. reflexivity. }
    change (path_expr ce ex (PField f :: p)) with (path_expr ce (step_expr ce ex (PField f)) p).
    rewrite SE.
    destruct (IH tf t' (Efield ex f (ctype_of_ftype tf)) b (q0 ++ [Sfield f])) as [A B]; auto.
    + apply find_assoc_In in Ff. apply find_msg_In in F. eapply fields_ok; [apply F | eauto].
    + cbn [eval_lvalue]. unfold lvalue_field. rewrite T, E. reflexivity.
    + rewrite A, <- app_assoc. split; auto.
  - destruct t as [q|id|tf n]; simpl in R; try discriminate.
    destruct ((0 <=? i)%Z && (i <? n)%Z)%bool eqn:Hi; try discriminate.
    simpl in Ht. rewrite !andb_true_iff in Ht. destruct Ht as [[Hn1 Hn2] Htf].
    rewrite andb_true_iff, Z.leb_le, Z.ltb_lt in Hi. apply Z.leb_le in Hn2.
    assert (SE: step_expr ce ex (PIndex i) = Eindex ex (Econst_int i tint) (ctype_of_ftype tf)).
    { unfold step_expr, step_type. rewrite T. reflexivity. }
    change (path_expr ce ex (PIndex i :: p)) with (path_expr ce (step_expr ce ex (PIndex i)) p).
    rewrite SE.
    destruct (IH tf t' (Eindex ex (Econst_int i tint) (ctype_of_ftype tf)) b (q0 ++ [Sindex i]))
      as [A B]; auto.
    + cbn [eval_lvalue]. unfold lvalue_index. rewrite T, E.
      simpl. replace (wrap_signed 32 i) with i by (symmetry; apply (norm_int_index i); lia).
      replace (Z.leb 0 i && Z.ltb i n)%bool with true
        by (symmetry; apply andb_true_iff; split; [apply Z.leb_le | apply Z.ltb_lt]; lia).
      reflexivity.
    + rewrite A, <- app_assoc. split; auto.
Qed.

Lemma path_expr_lvalue_form:
  forall p ex, p <> [] ->
  (exists a f ty, path_expr ce ex p = Efield a f ty) \/ (exists a i ty, path_expr ce ex p = Eindex a i ty).
Proof.
  induction p as [|s p IH]; intros ex N; [congruence|].
  destruct p as [|s' p].
  - destruct s; simpl; [left | right]; eauto.
  - simpl. apply (IH (step_expr ce ex s)). discriminate.
Qed.

(** Reading a leaf [e.p] of a message: a scalar load of the leaf's type. *)
Lemma eval_leaf:
  forall ge e le mm M p q ex b q0,
  resolve msgs (FTmsg M) p = Some (FTprim q) ->
  typeof ex = Tstruct M -> eval_lvalue ge e le mm ex = Some (b, q0) ->
     eval_lvalue ge e le mm (path_expr ce ex p) = Some (b, q0 ++ path_steps p)
  /\ typeof (path_expr ce ex p) = ctype_of_prim q
  /\ eval_expr ge e le mm (path_expr ce ex p) = load (ctype_of_prim q) mm b (q0 ++ path_steps p).
Proof.
  intros ge e le mm M p q ex b q0 R T E.
  assert (HM: In M (md_names msgs)) by (eapply resolve_leaf_msg; eauto).
  destruct (eval_lvalue_path ge e le mm p (FTmsg M) (FTprim q) ex b q0) as [A B]; auto.
  { apply ftype_ok_msg; auto. }
  split; [exact A|]. split; [exact B|].
  assert (N: p <> []) by (intros ->; discriminate R).
  destruct (path_expr_lvalue_form p ex N) as [(a & f & ty & Ea)|(a & i & ty & Ea)];
    rewrite Ea in *.
  - rewrite (eval_expr_lvalue ge e le mm (Efield a f ty) I). simpl in B. subst ty.
    simpl typeof. rewrite A. reflexivity.
  - rewrite (eval_expr_lvalue ge e le mm (Eindex a i ty) I). simpl in B. subst ty.
    simpl typeof. rewrite A. reflexivity.
Qed.

End MODEL.

(** ** Execution of the copy template *)

Lemma ctype_of_prim_scalar_type: forall q, is_scalar_type (ctype_of_prim q) = true.
Proof. destruct q; reflexivity. Qed.

(** A scalar assignment stores the converted value. *)
Lemma eval_assign_scalar:
  forall ge e le mm a1 a2 b p v,
  eval_lvalue ge e le mm a1 = Some (b, p) ->
  is_scalar_type (typeof a1) = true ->
  eval_expr ge e le mm a2 = Some v ->
  eval_assign ge e le mm a1 a2 = store (typeof a1) mm b p v.
Proof.
  intros ge e le mm a1 a2 b p v L S E. unfold eval_assign. rewrite L.
  destruct (typeof a1); try discriminate S; rewrite E; reflexivity.
Qed.

(** [tmp = src; dst = tmp;] stores the value of [src] at [dst]. *)
Lemma exec_copy:
  forall CS (ctx : ros_context CS) ge e le mm w q dst src v b p mm',
  eval_expr ge e le mm src = Some v ->
  val_has_type v (ctype_of_prim q) ->
  eval_lvalue ge e (set_assoc (temp_name q) v le) mm dst = Some (b, p) ->
  typeof dst = ctype_of_prim q ->
  store_path mm b p (MVscalar v) = Some mm' ->
  exec_stmt ctx ge e le mm w (copy q dst src) [] (set_assoc (temp_name q) v le) mm' w Out_normal.
Proof.
  intros CS ctx ge e le mm w q dst src v b p mm' Es Tv Ld Td S.
  unfold copy. change (@nil event) with (@nil event ++ @nil event). eapply exec_Sseq_1.
  - apply exec_Sset; eauto.
  - apply exec_Sassign.
    rewrite (eval_assign_scalar ge e _ mm dst _ b p v Ld).
    + rewrite Td. unfold store. rewrite sem_cast_same; auto.
    + rewrite Td. apply ctype_of_prim_scalar_type.
    + simpl. apply find_assoc_set_same.
Qed.

(** [dst = 0;] for a scalar leaf. *)
Lemma eval_zero_of:
  forall ge e le mm q, eval_expr ge e le mm (zero_of q) = Some (zero_val (ctype_of_prim q)).
Proof. intros; destruct q; reflexivity. Qed.

Lemma sem_cast_zero:
  forall q, sem_cast (zero_val (ctype_of_prim q)) (ctype_of_prim q) = Some (zero_val (ctype_of_prim q)).
Proof. destruct q; reflexivity. Qed.

Lemma zero_mval_prim:
  forall ce q, zero_mval ce (ctype_of_prim q) = MVscalar (zero_val (ctype_of_prim q)).
Proof. intros; destruct q; reflexivity. Qed.

Lemma exec_zero:
  forall CS (ctx : ros_context CS) ge e le mm w q dst b p mm',
  eval_lvalue ge e le mm dst = Some (b, p) ->
  typeof dst = ctype_of_prim q ->
  store_path mm b p (MVscalar (zero_val (ctype_of_prim q))) = Some mm' ->
  exec_stmt ctx ge e le mm w (Sassign dst (zero_of q)) [] le mm' w Out_normal.
Proof.
  intros CS ctx ge e le mm w q dst b p mm' Ld Td S.
  apply exec_Sassign. rewrite (eval_assign_scalar ge e le mm dst _ b p (zero_val (ctype_of_prim q)) Ld).
  - rewrite Td. unfold store. rewrite sem_cast_zero. auto.
  - rewrite Td. apply ctype_of_prim_scalar_type.
  - apply eval_zero_of.
Qed.

(** A store into a block holding a typed value, at a typed path, of a
    value of that type. *)
Lemma store_typed:
  forall ce mm b ty v p t x,
  get_block mm b = Some (ty, v) -> mval_has_type ce ty v -> type_at ce ty p = Some t ->
  mval_has_type ce t x ->
  exists mm' v', store_path mm b p x = Some mm'
    /\ mval_set v p x = Some v'
    /\ get_block mm' b = Some (ty, v') /\ mval_has_type ce ty v'
    /\ mem_next mm' = mem_next mm
    /\ forall b', b' <> b -> get_block mm' b' = get_block mm b'.
Proof.
  intros ce mm b ty v p t x G Hv T Hx.
  destruct (mval_set_has_type ce p ty v t x Hv T Hx) as [v' [S Hv']].
  exists (mkmem (pset b (ty, v') (mem_contents mm)) (mem_next mm)), v'.
  unfold store_path. rewrite G, S. repeat split; auto.
  - unfold get_block; simpl; apply pgss.
  - intros b' N. unfold get_block; simpl; apply pgso; auto.
Qed.

(** ** Sequences of copies *)

(** A sequence of copies [dst_a = src_a] for the items [a] of a list,
    every destination a scalar at path [dp a] in the same block [bd],
    every source read from other blocks, the paths pairwise disjoint. *)
Section COPIES.

Context {CS : Type}.
Variable ctx : ros_context CS.
Variable ge : genv.
Variable e : env.
Variable w : world CS.
Variable ce : composite_env.

Variable A : Type.
Variable qf : A -> prim.
Variables dst src : A -> expr.
Variable dp : A -> Values.path.
Variable sv : A -> val.

(** What the temporaries must satisfy for the sources and destinations
    to evaluate (the pointer parameter, if any, is unchanged). *)
Variable le_ok : temp_env -> Prop.
Hypothesis le_ok_set: forall le q v, le_ok le -> le_ok (set_assoc (temp_name q) v le).

Variable mm0 : mem.
Variable bd : block.
Variable tyd : type.

Definition copies_stmt (L : list A) : statement :=
  seq_of (map (fun a => copy (qf a) (dst a) (src a)) L).

Definition frame (mm : mem) : Prop :=
  mem_next mm = mem_next mm0 /\ forall b', b' <> bd -> get_block mm b' = get_block mm0 b'.

Definition item_ok (a : A) : Prop :=
  (forall le mm, le_ok le -> frame mm -> eval_expr ge e le mm (src a) = Some (sv a))
  /\ (forall le mm, le_ok le -> eval_lvalue ge e le mm (dst a) = Some (bd, dp a))
  /\ typeof (dst a) = ctype_of_prim (qf a)
  /\ val_has_type (sv a) (ctype_of_prim (qf a))
  /\ type_at ce tyd (dp a) = Some (ctype_of_prim (qf a)).

Lemma exec_copies:
  forall L le mm v,
  le_ok le -> frame mm ->
  get_block mm bd = Some (tyd, v) -> mval_has_type ce tyd v ->
  (forall a, In a L -> item_ok a) ->
  NoDup (map dp L) ->
  (forall a1 a2, In a1 L -> In a2 L -> dp a1 <> dp a2 -> path_disjoint (dp a1) (dp a2)) ->
  exists le' mm' v',
     exec_stmt ctx ge e le mm w (copies_stmt L) [] le' mm' w Out_normal
  /\ le_ok le' /\ frame mm'
  /\ get_block mm' bd = Some (tyd, v') /\ mval_has_type ce tyd v'
  /\ (forall a, In a L -> mval_get v' (dp a) = Some (MVscalar (sv a)))
  /\ (forall p', (forall a, In a L -> path_disjoint (dp a) p') -> mval_get v' p' = mval_get v p').
Proof.
  induction L as [|a L IH]; intros le mm v Hle Fr G Hv OK ND DJ.
  - exists le, mm, v. repeat split; auto; try apply Fr.
    + apply exec_Sskip.
    + intros a [].
  - destruct (OK a (or_introl eq_refl)) as (Hs & Hd & Td & Tv & Tp).
    assert (Hx: mval_has_type ce (ctype_of_prim (qf a)) (MVscalar (sv a)))
      by (constructor; auto; apply ctype_of_prim_scalar_type).
    destruct (store_typed ce mm bd tyd v (dp a) _ _ G Hv Tp Hx)
      as (mm1 & v1 & S & Sv & G1 & Hv1 & N1 & O1).
    assert (Fr1: frame mm1).
    { destruct Fr as [Fn Fo]. split; [congruence|]. intros b' Nb. rewrite O1; auto. }
    simpl in ND. inversion ND as [|? ? Hnin ND']; subst.
    destruct (IH (set_assoc (temp_name (qf a)) (sv a) le) mm1 v1) as
      (le' & mm' & v' & X & Hle' & Fr' & G' & Hv' & Set' & Keep');
      auto; try (intros; apply OK; simpl; auto).
    { intros a1 a2 H1 H2; apply DJ; simpl; auto. }
    exists le', mm', v'. repeat split; auto; try apply Fr'.
    + unfold copies_stmt; simpl. change (@nil event) with (@nil event ++ @nil event).
      eapply exec_Sseq_1; [|exact X].
      eapply exec_copy; eauto.
    + intros a' [<-|Ha'].
      * rewrite Keep'. { eapply mval_get_set_same; eauto. }
        intros a2 Ha2. apply DJ; simpl; auto. intros E; apply Hnin. rewrite <- E; apply in_map; auto.
      * apply Set'; auto.
    + intros p' Dp. rewrite Keep' by (intros; apply Dp; simpl; auto).
      eapply mval_get_set_disjoint; eauto. apply Dp; simpl; auto.
Qed.

End COPIES.
