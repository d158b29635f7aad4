(** * Facts for the proof of the generated glue functions (theorem T1) *)

(** Generic facts on values and sequences of statements, the equalities
    between the constants of the specification ([DDC]) and the
    generator's, and the facts of a generated program that the proofs of
    its callbacks and input glue ([Inputproof]) and of its output glue
    ([Outputproof]) share: its types, functions and globals, the scalar
    globals, the clock of a timed topic (rule 4.12).  T1 itself is
    stated in [Glueproof]. *)

From Coq Require Import String List ZArith Bool Lia.
From ROSGen Require Import Errors Maps Syntax Values Operators Memory Environment Semantics NodeModel Wellformed Generator Generatorspec Generatorproof.
From ROSGen Require Import DDC Copyproof.
Import ListNotations.

Local Open Scope list_scope.

(** ** Generic facts *)

(** The scalar at path [p] of [v] ([Vundef] if there is none). *)
Definition scalar_at (v : mval) (p : Values.path) : val :=
  match mval_get v p with Some (MVscalar x) => x | _ => Vundef end.

Lemma scalar_at_spec:
  forall v p x, mval_get v p = Some (MVscalar x) -> scalar_at v p = x.
Proof. intros v p x H; unfold scalar_at; rewrite H; auto. Qed.

Lemma path_steps_inj: forall p1 p2, path_steps p1 = path_steps p2 -> p1 = p2.
Proof.
  induction p1 as [|s1 p1 IH]; intros [|s2 p2] E; simpl in E; try discriminate; auto.
  inversion E. f_equal; auto. apply step_of_pstep_inj; auto.
Qed.

Lemma type_step_field:
  forall ce id f, type_step ce (Tstruct id) (Sfield f) = Generator.field_type ce id f.
Proof.
  intros; simpl. unfold struct_members, Generator.field_type, Values.field_type.
  destruct (find_composite id ce); auto.
Qed.

(** A function whose body runs quietly from its entry state meets
    [quiet_call_at] (its [post] sees the world's time), and [quiet_call]. *)
Lemma quiet_call_at_intro:
  forall p f args mm le post,
  function_entry (ge_comp (globalenv p)) f args mm = Some ([], le, mm) ->
  fn_return f = Tvoid ->
  (forall (CS : Type) (ctx : ros_context CS) (w : world CS),
     exists le' mm', exec_stmt ctx (globalenv p) [] le mm w (fn_body f) [] le' mm' w Out_normal
                     /\ post (w_time w) mm') ->
  quiet_call_at p (Internal f) args mm post.
Proof.
  intros p f args mm le post FE R X CS ctx w.
  destruct (X CS ctx w) as (le' & mm' & E & P).
  assert (EV: eval_funcall ctx (globalenv p) mm w (Internal f) args [] mm' w Vundef).
  { change mm' with (free_vars mm' []). econstructor; eauto; rewrite R; auto. }
  split; [eauto|].
  intros t mm2 w2 v2 EV2.
  destruct (semantics_determ ctx (globalenv p)) as [_ [D _]].
  destruct (D _ _ _ _ _ _ _ _ EV _ _ _ _ EV2) as (<- & <- & <- & <-). auto.
Qed.

Lemma quiet_call_intro:
  forall p f args mm le post,
  function_entry (ge_comp (globalenv p)) f args mm = Some ([], le, mm) ->
  fn_return f = Tvoid ->
  (forall (CS : Type) (ctx : ros_context CS) (w : world CS),
     exists le' mm', exec_stmt ctx (globalenv p) [] le mm w (fn_body f) [] le' mm' w Out_normal
                     /\ post mm') ->
  quiet_call p (Internal f) args mm post.
Proof.
  intros p f args mm le post FE R X.
  exact (quiet_call_at_intro p f args mm le (fun _ => post) FE R X).
Qed.

Lemma eval_lvalue_global_struct:
  forall ge le mm x id b ty,
  find_var ge x = Some (b, ty) -> eval_lvalue ge [] le mm (Evar x (Tstruct id)) = Some (b, []).
Proof. intros ge le mm x id b ty H. cbn [eval_lvalue]. unfold lvalue_var. simpl. rewrite H; auto. Qed.

Lemma eval_lvalue_field:
  forall ge e le mm a f ty b q id,
  typeof a = Tstruct id -> eval_lvalue ge e le mm a = Some (b, q) ->
  eval_lvalue ge e le mm (Efield a f ty) = Some (b, q ++ [Sfield f]).
Proof. intros. cbn [eval_lvalue]. unfold lvalue_field. rewrite H, H0. auto. Qed.

Lemma eval_lvalue_deref_param:
  forall ge e le mm x M b,
  find_assoc x le = Some (Vptr b []) -> eval_lvalue ge e le mm (deref_param x M) = Some (b, []).
Proof. intros; unfold deref_param; cbn [eval_lvalue eval_expr]; rewrite H; auto. Qed.

Lemma temp_name_not_param: forall q, temp_name q <> msg_param /\ temp_name q <> command_param.
Proof. destruct q; split; discriminate. Qed.

Lemma frame_unchanged:
  forall mm0 bd mm, frame mm0 bd mm -> unchanged_except mm0 mm bd.
Proof. intros mm0 bd mm [A B]; split; auto. Qed.

(** Sequences of statements. *)
Section SEQ.

Context {CS : Type}.
Variable ctx : ros_context CS.
Variable ge : genv.

Lemma exec_seq_of_app:
  forall l1 l2 e le mm w t1 le1 mm1 w1 t2 le2 mm2 w2 out,
  exec_stmt ctx ge e le mm w (seq_of l1) t1 le1 mm1 w1 Out_normal ->
  exec_stmt ctx ge e le1 mm1 w1 (seq_of l2) t2 le2 mm2 w2 out ->
  exec_stmt ctx ge e le mm w (seq_of (l1 ++ l2)) (t1 ++ t2) le2 mm2 w2 out.
Proof.
  induction l1 as [|s l1 IH]; intros l2 e le mm w t1 le1 mm1 w1 t2 le2 mm2 w2 out X1 X2.
  - simpl in X1. inversion X1; subst. exact X2.
  - simpl in X1 |- *. inversion X1; subst; [|congruence].
    rewrite <- app_assoc. eapply exec_Sseq_1; eauto.
Qed.

Lemma exec_seq_cons:
  forall s l e le mm w le1 mm1 w1 t le2 mm2 w2 out,
  exec_stmt ctx ge e le mm w s [] le1 mm1 w1 Out_normal ->
  exec_stmt ctx ge e le1 mm1 w1 (seq_of l) t le2 mm2 w2 out ->
  exec_stmt ctx ge e le mm w (seq_of (s :: l)) t le2 mm2 w2 out.
Proof.
  intros. simpl. change t with ([] ++ t). eapply exec_Sseq_1; eauto.
Qed.

End SEQ.

(** ** The specification's constants are the generator's *)

(** [DDC] states its constants itself (it does not load [Generator]);
    these are the equalities the proofs use. *)

(** The largest [unsigned long long] of the specification ([2^64 - 1]) is
    the generator's [max_ulong]. *)
Lemma ulong_max_agrees: DDC.ulong_max = max_ulong.
Proof. reflexivity. Qed.

(** The largest [unsigned int] of the specification ([2^32 - 1]) is the
    generator's [max_uint], where it saturates [age_ms]. *)
Lemma uint_max_agrees: DDC.uint_max = max_uint.
Proof. reflexivity. Qed.

(** The specification's timeout in nanoseconds is the generator's
    timeout in milliseconds ([Wellformed.timeout_of]) times [10^6]. *)
Lemma timeout_ns_agrees:
  forall m c, timeout_ns m c = option_map (fun t => t * 1000000)%Z (timeout_of m c).
Proof. intros m c. unfold timeout_ns, timeout_of. destruct (find_assoc c (nm_timeouts m)); reflexivity. Qed.

(** ** The generated program *)

Section GENERATED.

Variable m : node_model.
Variable p : program.
Hypothesis GEN : generate m = OK p.

Let W : wf_facts m := wf_facts_intro m (generate_sound m p GEN).
Let ND : NoDup (map fst (prog_defs p)) := generate_names_distinct m p GEN.

Local Notation ge := (globalenv p).
Local Notation ce := (composites m).
Local Notation msgs := (nm_msgs m).

Lemma gen_types: prog_types p = ce.
Proof. apply (generate_types m p GEN). Qed.

Lemma gen_comp: ge_comp ge = ce.
Proof. rewrite globalenv_comp; apply gen_types. Qed.

Lemma gen_funct: forall id fd, find_def p id = Some (Gfun fd) -> find_funct ge id = Some fd.
Proof. intros; apply find_funct_globalenv; auto. Qed.

Lemma gen_var: forall x ty, find_def p x = Some (Gvar ty) -> exists b, find_var ge x = Some (b, ty).
Proof. intros; apply globalenv_find_var; auto. Qed.

Lemma gen_msg_in: forall tp, In tp (nm_topics m) -> In (tp_msg tp) (md_names msgs).
Proof.
  intros tp H. generalize (wf_topics m W tp H). unfold topic_ok.
  destruct (find_msg msgs (tp_msg tp)) as [md|] eqn:F; [|rewrite andb_false_r; discriminate].
  intros _. apply find_msg_In in F. destruct F as [F <-]. apply in_map; auto.
Qed.

Lemma gen_leaf:
  forall M lp q, In (lp, q) (leaves msgs M) -> resolve msgs (FTmsg M) lp = Some (FTprim q).
Proof. intros; apply leaves_spec; auto. Qed.

Lemma gen_leaves_dp_nodup:
  forall M, NoDup (map (fun l : NodeModel.path * prim => path_steps (fst l)) (leaves msgs M)).
Proof.
  intros M. rewrite <- (map_map fst path_steps). apply NoDup_map_inj.
  - apply path_steps_inj.
  - apply leaves_nodup; auto.
Qed.

Lemma gen_leaves_disjoint:
  forall M (l1 l2 : NodeModel.path * prim), In l1 (leaves msgs M) -> In l2 (leaves msgs M) ->
  path_steps (fst l1) <> path_steps (fst l2) ->
  path_disjoint (path_steps (fst l1)) (path_steps (fst l2)).
Proof.
  intros M [p1 q1] [p2 q2] H1 H2 N. simpl in *.
  apply (leaves_disjoint m p1 p2 (FTmsg M) q1 q2); try apply gen_leaf; auto.
  congruence.
Qed.

Lemma gen_wf_composites: wf_composites ce.
Proof. apply wf_composites_of; auto. Qed.

Lemma gen_zero_typed:
  forall M, In M (md_names msgs) -> mval_has_type ce (Tstruct M) (zero_mval ce (Tstruct M)).
Proof.
  intros M HM. apply zero_mval_has_type; [apply gen_wf_composites|].
  simpl. apply in_ident_spec. unfold composite_names, composites.
  rewrite map_app, map_map. apply in_or_app; left. exact HM.
Qed.

Lemma gen_zero_leaf:
  forall M lp q, resolve msgs (FTmsg M) lp = Some (FTprim q) ->
  mval_get (zero_mval ce (Tstruct M)) (path_steps lp) = Some (zero_mval ce (ctype_of_prim q)).
Proof.
  intros M lp q R. assert (HM: In M (md_names msgs)) by (eapply resolve_leaf_msg; eauto).
  apply mval_get_zero; [apply gen_wf_composites| |].
  - simpl. apply in_ident_spec. unfold composite_names, composites.
    rewrite map_app, map_map. apply in_or_app; left. exact HM.
  - change (Tstruct M) with (ctype_of_ftype (FTmsg M)). rewrite type_at_ctype; auto.
    + rewrite R; reflexivity.
    + apply ftype_ok_msg; auto.
Qed.

(** ** Scalar globals and the clock (rule 4.12) *)

Lemma gen_timed_sub: forall tp, In tp (timed m) -> In tp (subscribed m).
Proof. intros tp H. unfold timed in H. apply filter_In in H. tauto. Qed.

Lemma gen_timed_is: forall tp, In tp (timed m) -> is_timed m (tp_cname tp) = true.
Proof. intros tp H. unfold timed in H. apply filter_In in H. tauto. Qed.

Lemma gen_timed_nonempty: forall tp, In tp (timed m) -> timed m <> [].
Proof. intros tp H E; rewrite E in H; contradiction. Qed.

(** [x = rhs;] for a scalar global [x]: only [x] changes. *)
Lemma exec_assign_global:
  forall (CS : Type) (ctx : ros_context CS) (w : world CS) le mm x bx ty v0 rhs v,
  find_var ge x = Some (bx, ty) -> get_block mm bx = Some (ty, v0) -> is_scalar_type ty = true ->
  eval_expr ge [] le mm rhs = Some v -> val_has_type v ty ->
  exists mm',
     exec_stmt ctx ge [] le mm w (Sassign (Evar x ty) rhs) [] le mm' w Out_normal
  /\ only_global_changed p mm mm' x (MVscalar v)
  /\ get_block mm' bx = Some (ty, MVscalar v)
  /\ unchanged_except mm mm' bx.
Proof.
  intros CS ctx w le mm x bx ty v0 rhs v V G S E T.
  set (mm' := mkmem (pset bx (ty, MVscalar v) (mem_contents mm)) (mem_next mm)).
  assert (G': get_block mm' bx = Some (ty, MVscalar v)) by (unfold get_block, mm'; simpl; apply pgss).
  assert (U: unchanged_except mm mm' bx).
  { split; auto. intros b' N. unfold get_block, mm'; simpl; apply pgso; auto. }
  exists mm'. split; [|split; [exists bx, ty; split; [|split]; auto|split; auto]].
  apply exec_Sassign.
  rewrite (eval_assign_scalar ge [] le mm (Evar x ty) rhs bx [] v); auto.
  - simpl. unfold store. rewrite sem_cast_same by exact T. unfold store_path. rewrite G. reflexivity.
  - cbn [eval_lvalue]. unfold lvalue_var. simpl. rewrite V. destruct ty; auto; discriminate.
Qed.

(** [x = f();] for an external [f] of the ROS API that answers [v]
    without an event or an effect. *)
Lemma exec_call0_external:
  forall (CS : Type) (ctx : ros_context CS) (w : world CS) le mm1 f ef ty x v,
  find_def p f = Some (Gfun (External ef [] ty)) ->
  (forall mm0, external_call ctx ge ef [] mm0 w = Some (v, [], mm0, w)) ->
  exec_stmt ctx ge [] le mm1 w (Scall (Some x) (Evar f (Tfunction [] ty)) []) [] (set_assoc x v le) mm1 w Out_normal.
Proof.
  intros CS ctx w le mm1 f ef ty x v F EC.
  change (set_assoc x v le) with (set_opttemp (Some x) v le).
  eapply exec_Scall.
  - cbn [eval_expr]. unfold eval_funcname. simpl.
    destruct (find_var ge f) as [[bf tf]|] eqn:V.
    + apply find_var_globalenv in V; [congruence|exact ND].
    + rewrite (gen_funct _ _ F). reflexivity.
  - apply gen_funct; exact F.
  - reflexivity.
  - reflexivity.
  - reflexivity.
  - apply eval_funcall_external. apply EC.
Qed.

(** [x = ros_now();] *)
Lemma exec_now_call:
  forall (CS : Type) (ctx : ros_context CS) (w : world CS) le mm1 x,
  timed m <> [] ->
  exec_stmt ctx ge [] le mm1 w (now_call x) [] (set_assoc x (Vlong (clock (w_time w))) le) mm1 w Out_normal.
Proof.
  intros CS ctx w le mm1 x NE.
  apply (exec_call0_external CS ctx w le mm1 _ _ _ x _ (generate_now_external m p GEN NE)).
  reflexivity.
Qed.

(** Replacing the value of a global by a value of its type keeps the
    globals typed. *)
Lemma globals_typed_changed:
  forall mm mm' x v,
  globals_typed p mm -> only_global_changed p mm mm' x v ->
  (forall b ty, find_var ge x = Some (b, ty) -> mval_has_type ce ty v) ->
  globals_typed p mm'.
Proof.
  intros mm mm' x v GT (bx & tx & Vx & Gx & [Nn No]) Tv y b ty Vy.
  destruct (Pos.eq_dec b bx) as [->|Nb].
  - destruct (string_dec x y) as [->|Nxy].
    + rewrite Vx in Vy; inversion Vy; subst. exists v; split; auto. rewrite gen_types; eapply Tv; eauto.
    + exfalso. eapply (globalenv_vars_disjoint p x y bx tx bx ty); eauto.
  - rewrite No; auto. apply (GT _ _ _ Vy).
Qed.

Lemma append_cancel: forall s a b, (s ++ a)%string = (s ++ b)%string -> a = b.
Proof. induction s as [|c s IH]; simpl; intros a b E; auto. inversion E; auto. Qed.

Lemma clock_names_distinct:
  forall c, time_var c <> new_var c /\ time_var c <> rcvd_var c /\ new_var c <> rcvd_var c
         /\ msg_var c <> time_var c /\ msg_var c <> new_var c /\ msg_var c <> rcvd_var c.
Proof.
  intros c; unfold time_var, new_var, rcvd_var, msg_var.
  repeat split; intros E; apply append_cancel in E; discriminate.
Qed.

(** A global of the program and its block, holding a value of its type. *)
Lemma gen_global_block:
  forall mm x ty, globals_typed p mm -> find_def p x = Some (Gvar ty) ->
  exists bx v0, find_var ge x = Some (bx, ty) /\ get_block mm bx = Some (ty, v0).
Proof.
  intros mm x ty GT F. destruct (gen_var _ _ F) as [bx V].
  destruct (GT _ _ _ V) as (v0 & G & _). eauto.
Qed.

(** The clock update of a timed topic's callback:
    [_t_ullong = ros_now(); c_time = _t_ullong; c_new = 1; c_rcvd = 1;]. *)
Lemma clock_run:
  forall tp (CS : Type) (ctx : ros_context CS) (w : world CS) le mm1,
  In tp (timed m) -> globals_typed p mm1 ->
  exists le' mm',
     exec_stmt ctx ge [] le mm1 w (clock_stmts (tp_cname tp)) [] le' mm' w Out_normal
  /\ globals_typed p mm'
  /\ globals_changed p mm1 mm'
       [(time_var (tp_cname tp), MVscalar (Vlong (clock (w_time w))));
        (new_var (tp_cname tp), MVscalar (Vint 1)); (rcvd_var (tp_cname tp), MVscalar (Vint 1))].
Proof.
  intros tp CS ctx w le mm1 Ht GT1.
  destruct (generate_clock_globals m p tp GEN Ht) as (Ft & Fn & Fr).
  set (c := tp_cname tp) in *.
  set (le1 := set_assoc (temp_name Puint64) (Vlong (clock (w_time w))) le).
  assert (TC: val_has_type (Vlong (clock (w_time w))) (Tlong Unsigned))
    by (unfold val_has_type, clock; apply norm_long_idem).
  destruct (gen_global_block mm1 _ _ GT1 Ft) as (bt & vt & Vt & Gt).
  assert (E1: eval_expr ge [] le1 mm1 (Etempvar (temp_name Puint64) tulong) = Some (Vlong (clock (w_time w))))
    by (simpl; unfold le1; apply find_assoc_set_same).
  destruct (exec_assign_global CS ctx w le1 mm1 (time_var c) bt _ vt
              (Etempvar (temp_name Puint64) tulong) (Vlong (clock (w_time w))) Vt Gt eq_refl E1 TC)
    as (mm2 & X2 & O2 & _).
  assert (GT2: globals_typed p mm2).
  { eapply globals_typed_changed; eauto. intros b ty V. rewrite Vt in V; inversion V; subst.
    constructor; auto. }
  destruct (gen_global_block mm2 _ _ GT2 Fn) as (bn & vn & Vn & Gn).
  destruct (exec_assign_global CS ctx w le1 mm2 (new_var c) bn _ vn (Econst_int 1 tflag) (Vint 1) Vn Gn
              eq_refl eq_refl eq_refl)
    as (mm3 & X3 & O3 & _).
  assert (GT3: globals_typed p mm3).
  { eapply globals_typed_changed; eauto. intros b ty V. rewrite Vn in V; inversion V; subst.
    constructor; auto. reflexivity. }
  destruct (gen_global_block mm3 _ _ GT3 Fr) as (br & vr & Vr & Gr).
  destruct (exec_assign_global CS ctx w le1 mm3 (rcvd_var c) br _ vr (Econst_int 1 tflag) (Vint 1) Vr Gr
              eq_refl eq_refl eq_refl)
    as (mm4 & X4 & O4 & _).
  assert (GT4: globals_typed p mm4).
  { eapply globals_typed_changed; eauto. intros b ty V. rewrite Vr in V; inversion V; subst.
    constructor; auto. reflexivity. }
  exists le1, mm4. split; [|split; auto].
  - unfold clock_stmts. cbn [seq_of].
    change (@nil event) with (@nil event ++ @nil event).
    eapply exec_Sseq_1; [apply exec_now_call; eapply gen_timed_nonempty; eauto|].
    change (@nil event) with (@nil event ++ @nil event).
    eapply exec_Sseq_1; [exact X2|].
    change (@nil event) with (@nil event ++ @nil event).
    eapply exec_Sseq_1; [exact X3|].
    change (@nil event) with (@nil event ++ @nil event).
    eapply exec_Sseq_1; [exact X4|]. apply exec_Sskip.
  - econstructor; [exact O2|]. econstructor; [exact O3|]. econstructor; [exact O4|]. constructor.
Qed.

End GENERATED.
