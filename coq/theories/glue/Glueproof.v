(** * Correctness proof for the generated glue functions (theorem T1) *)

(** For every well-formed node model [m] and its program [p]
    ([generate m = OK p]), the generated callbacks, [input_glue] and
    [output_glue_c] meet the specifications of [DDC]: [callback_ddc]
    (the paper's Figure 10), [input_glue_ddc] (Figure 12) and
    [output_glue_ddc].  The proofs run the bodies symbolically with
    [Copyproof.exec_copies]: each body is a sequence of copies, one per
    leaf or relation, into one destination block, from other blocks. *)

From Coq Require Import String List ZArith Bool Lia.
From ROSGen Require Import Errors Maps Syntax Values Memory Environment Semantics NodeModel Wellformed Generator Generatorspec Generatorproof.
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

(** ** Callbacks (Figure 10) *)

Section CALLBACK.

Variable tp : topic.
Hypothesis Htp : In tp (subscribed m).
Local Notation c := (tp_cname tp).
Local Notation M := (tp_msg tp).

Variables (mm : mem) (b bg : block) (mv : mval).
Hypothesis Vg : find_var ge (msg_var c) = Some (bg, Tstruct M).
Hypothesis Gb : get_block mm b = Some (Tstruct M, mv).
Hypothesis Hmv : mval_has_type ce (Tstruct M) mv.
Hypothesis Nb : b <> bg.

Let dstE := Evar (msg_var c) (Tstruct M).
Let srcE := deref_param msg_param M.
Let le_ok (le : temp_env) : Prop := find_assoc msg_param le = Some (Vptr b []).
Let sv (l : NodeModel.path * prim) : val := scalar_at mv (path_steps (fst l)).

Lemma callback_le_ok_set: forall le q v, le_ok le -> le_ok (set_assoc (temp_name q) v le).
Proof.
  intros le q v H. unfold le_ok. rewrite find_assoc_set_other; auto.
  intros E; apply (proj1 (temp_name_not_param q)); auto.
Qed.

Lemma callback_item_ok:
  forall l, In l (leaves msgs M) ->
  item_ok ge [] ce _ snd (fun l => path_expr ce dstE (fst l)) (fun l => path_expr ce srcE (fst l))
          (fun l => path_steps (fst l)) sv le_ok mm bg (Tstruct M) l.
Proof.
  intros [lp q] Hl. apply gen_leaf in Hl. unfold item_ok; cbn [fst snd].
  destruct (leaf_typed m W M lp q mv Hl Hmv) as (x & Gx & Tx).
  assert (Sx: sv (lp, q) = x) by (apply scalar_at_spec; auto).
  repeat split.
  - intros le mm1 Hle [Fn Fo].
    destruct (eval_leaf m W ge [] le mm1 M lp q srcE b [] Hl) as (_ & _ & E); auto.
    { apply eval_lvalue_deref_param; auto. }
    rewrite E, Sx. apply load_spec; [apply ctype_of_prim_scalar_type|].
    unfold load_path. rewrite Fo by auto. rewrite Gb. auto.
  - intros le mm1 Hle.
    destruct (eval_leaf m W ge [] le mm1 M lp q dstE bg [] Hl) as (A & _ & _); auto.
    eapply eval_lvalue_global_struct; eauto.
  - destruct (eval_leaf m W ge [] [] mm M lp q dstE bg [] Hl) as (_ & T & _); auto.
    eapply eval_lvalue_global_struct; eauto.
  - rewrite Sx; auto.
  - change (Tstruct M) with (ctype_of_ftype (FTmsg M)). rewrite type_at_ctype; auto.
    + rewrite Hl; reflexivity.
    + apply ftype_ok_msg. eapply resolve_leaf_msg; eauto.
Qed.

Lemma callback_body:
  forall (CS : Type) (ctx : ros_context CS) (w : world CS) le g0,
  le_ok le -> get_block mm bg = Some (Tstruct M, g0) -> mval_has_type ce (Tstruct M) g0 ->
  exists le' mm',
     exec_stmt ctx ge [] le mm w
       (seq_of (map (leaf_copy ce dstE srcE) (leaves msgs M))) [] le' mm' w Out_normal
  /\ get_block mm' bg = Some (Tstruct M, mv)
  /\ unchanged_except mm mm' bg.
Proof.
  intros CS ctx w le g0 Hle Gg Hg0.
  destruct (exec_copies ctx ge [] w ce _ snd (fun l => path_expr ce dstE (fst l))
              (fun l => path_expr ce srcE (fst l)) (fun l => path_steps (fst l)) sv
              le_ok callback_le_ok_set mm bg (Tstruct M) (leaves msgs M) le mm g0)
    as (le' & mm' & v' & X & _ & Fr & G' & Hv' & Set' & _); auto.
  - split; auto.
  - apply callback_item_ok.
  - apply gen_leaves_dp_nodup.
  - intros; apply (gen_leaves_disjoint M); auto.
  - exists le', mm'. split; [exact X|]. split; [|apply frame_unchanged; auto].
    rewrite G'. do 2 f_equal.
    assert (HM: In M (md_names msgs)).
    { apply gen_msg_in. apply in_subscribed in Htp; tauto. }
    apply (leaves_ext m W M mv v' HM Hmv); [eapply mval_shape_typed; eauto|].
    intros lp q R. apply leaves_spec in R; auto.
    generalize (Set' (lp, q) R); cbn [fst]; intros ->.
    apply leaves_spec in R; auto.
    destruct (leaf_typed m W M lp q mv R Hmv) as (x & Gx & _).
    rewrite Gx. unfold sv. simpl. rewrite (scalar_at_spec _ _ _ Gx). auto.
Qed.

End CALLBACK.

(** Every callback of a subscribed topic copies the whole message it is
    given into the topic's global, and changes nothing else. *)
Lemma generate_callback_ddc_aux:
  forall tp, In tp (subscribed m) -> callback_ddc m p tp.
Proof.
  intros tp Htp.
  destruct (generate_callback m p tp GEN Htp)
    as [Fv (f & Ff & Fret & Fpar & Fvars & Fbody & _ & _)].
  exists f. split; [apply gen_funct; auto|].
  intros mm b mv GT NG Gb Hmv. rewrite gen_types in Hmv.
  destruct (gen_var _ _ Fv) as [bg Vg].
  destruct (GT _ _ _ Vg) as (g0 & Gg & Hg0). rewrite gen_types in Hg0.
  assert (Nb: b <> bg) by (intros E; apply (NG _ _ _ Vg); auto).
  set (le0 := set_assoc msg_param (Vptr b []) (create_undef_temps (fn_temps f))).
  apply quiet_call_intro with (le := le0); auto.
  - unfold function_entry. rewrite Fvars, Fpar. reflexivity.
  - intros CS ctx w.
    destruct (callback_body tp Htp mm b bg mv Vg Gb Hmv Nb CS ctx w le0 g0) as (le' & mm' & X & G' & U); auto.
    + unfold le0. apply find_assoc_set_same.
    + exists le', mm'. rewrite Fbody, gen_types. split; auto.
      exists bg, (Tstruct (tp_msg tp)). auto.
Qed.

(** ** Input glue (Figure 12) *)

Lemma copies_map:
  forall (A : Type) (fq : A -> prim) (fd fs : A -> expr) l,
  copies (map fq l) (map fd l) (map fs l) = map (fun a => copy (fq a) (fd a) (fs a)) l.
Proof. induction l as [|a l IH]; simpl; f_equal; auto. Qed.

Lemma gen_in_out_vars:
  forall tp, In tp (subscribed m) -> msg_var (tp_cname tp) <> nm_in_var m /\ msg_var (tp_cname tp) <> nm_out_var m.
Proof.
  intros tp H. destruct (wf_controller_vars_fresh m W) as (_ & NU & NY).
  generalize (msg_var_in_after m tp H); intros Hin.
  split; intros E; [apply NU | apply NY]; rewrite <- E; auto.
Qed.

Section INPUT.

Variables (mm : mem) (bu : block).
Hypothesis GT : globals_typed p mm.
Hypothesis Vu : find_var ge (nm_in_var m) = Some (bu, Tstruct (nm_in_struct m)).

Let gval (ir : inrel) : mval :=
  match global_value p mm (msg_var (ir_topic ir)) with Some g => g | None => MVscalar Vundef end.
Let sv (ir : inrel) : val := scalar_at (gval ir) (path_steps (ir_path ir)).

Lemma input_source:
  forall ir, In ir (nm_inrels m) ->
  exists tp q bg g x,
     tp_cname tp = ir_topic ir /\ In tp (subscribed m)
  /\ find_assoc (ir_input ir) (nm_inputs m) = Some q
  /\ resolve msgs (FTmsg (tp_msg tp)) (ir_path ir) = Some (FTprim q)
  /\ input_prim (make_tables m) (ir_input ir) = q
  /\ input_src m (make_tables m) ir = path_expr ce (Evar (msg_var (ir_topic ir)) (Tstruct (tp_msg tp))) (ir_path ir)
  /\ input_dst m (make_tables m) ir = Efield (Evar (nm_in_var m) (Tstruct (nm_in_struct m))) (ir_input ir) (ctype_of_prim q)
  /\ find_var ge (msg_var (ir_topic ir)) = Some (bg, Tstruct (tp_msg tp))
  /\ get_block mm bg = Some (Tstruct (tp_msg tp), g)
  /\ bg <> bu
  /\ global_value p mm (msg_var (ir_topic ir)) = Some g
  /\ mval_get g (path_steps (ir_path ir)) = Some (MVscalar x)
  /\ val_has_type x (ctype_of_prim q)
  /\ sv ir = x.
Proof.
  intros ir Hir.
  destruct (input_exprs m ir W Hir) as (tp & q & _ & Ec & Hs & I & R & Pq & Es & Ed).
  destruct (generate_callback m p tp GEN Hs) as [Fv _].
  destruct (gen_var _ _ Fv) as [bg Vg]. rewrite Ec in Vg.
  destruct (GT _ _ _ Vg) as (g & Gg & Hg). rewrite gen_types in Hg.
  destruct (leaf_typed m W _ _ _ g R Hg) as (x & Gx & Tx).
  assert (GV: global_value p mm (msg_var (ir_topic ir)) = Some g)
    by (unfold global_value; rewrite Vg, Gg; auto).
  exists tp, q, bg, g, x. repeat split; auto.
  - eapply globalenv_vars_disjoint; eauto. rewrite <- Ec. apply gen_in_out_vars; auto.
  - unfold sv, gval. rewrite GV. apply scalar_at_spec; auto.
Qed.

Lemma input_item_ok:
  forall ir, In ir (nm_inrels m) ->
  item_ok ge [] ce _ (fun ir => input_prim (make_tables m) (ir_input ir)) (input_dst m (make_tables m)) (input_src m (make_tables m))
          (fun ir => [Sfield (ir_input ir)]) sv (fun _ => True) mm bu (Tstruct (nm_in_struct m)) ir.
Proof.
  intros ir Hir.
  destruct (input_source ir Hir) as (tp & q & bg & g & x & Ec & Hs & I & R & Pq & Es & Ed & Vg & Gg & Nbg & GV & Gx & Tx & Sx).
  unfold item_ok. rewrite Pq, Es, Ed, Sx. repeat split.
  - intros le mm1 _ [Fn Fo].
    destruct (eval_leaf m W ge [] le mm1 (tp_msg tp) (ir_path ir) q
                (Evar (msg_var (ir_topic ir)) (Tstruct (tp_msg tp))) bg [] R) as (_ & _ & E); auto.
    { eapply eval_lvalue_global_struct; eauto. }
    rewrite E. apply load_spec; [apply ctype_of_prim_scalar_type|].
    unfold load_path. rewrite Fo by auto. rewrite Gg. auto.
  - intros le mm1 _. change [Sfield (ir_input ir)] with ([] ++ [Sfield (ir_input ir)]).
    eapply eval_lvalue_field; [reflexivity|]. eapply eval_lvalue_global_struct; eauto.
  - auto.
  - cbn [type_at]. rewrite type_step_field, (field_type_inputs m W _ _ I). auto.
Qed.

Lemma input_body:
  forall (CS : Type) (ctx : ros_context CS) (w : world CS) le u0,
  get_block mm bu = Some (Tstruct (nm_in_struct m), u0) ->
  mval_has_type ce (Tstruct (nm_in_struct m)) u0 ->
  exists le' mm' u,
     exec_stmt ctx ge [] le mm w
       (seq_of (map (fun ir => copy (input_prim (make_tables m) (ir_input ir)) (input_dst m (make_tables m) ir) (input_src m (make_tables m) ir))
                    (nm_inrels m))) [] le' mm' w Out_normal
  /\ get_block mm' bu = Some (Tstruct (nm_in_struct m), u)
  /\ unchanged_except mm mm' bu
  /\ mval_has_type ce (Tstruct (nm_in_struct m)) u
  /\ forall ir, In ir (nm_inrels m) ->
       exists g v, global_value p mm (msg_var (ir_topic ir)) = Some g
         /\ mval_get g (path_steps (ir_path ir)) = Some (MVscalar v)
         /\ mval_get u [Sfield (ir_input ir)] = Some (MVscalar v).
Proof.
  intros CS ctx w le u0 Gu Hu0.
  destruct (exec_copies ctx ge [] w ce _ (fun ir => input_prim (make_tables m) (ir_input ir)) (input_dst m (make_tables m)) (input_src m (make_tables m))
              (fun ir => [Sfield (ir_input ir)]) sv (fun _ => True) (fun _ _ _ _ => I)
              mm bu (Tstruct (nm_in_struct m)) (nm_inrels m) le mm u0)
    as (le' & mm' & u & X & _ & Fr & G' & Hu & Set' & _); auto.
  - split; auto.
  - apply input_item_ok.
  - rewrite <- (map_map ir_input (fun x => [Sfield x])). apply NoDup_map_inj.
    + intros a b' E; inversion E; auto.
    + apply wf_inrel_inputs_nodup; auto.
  - intros a1 a2 _ _ N. simpl. left. congruence.
  - exists le', mm', u. repeat split; auto; try apply Fr.
    intros ir Hir.
    destruct (input_source ir Hir) as (tp & q & bg & g & x & _ & _ & _ & _ & _ & _ & _ & _ & _ & _ & GV & Gx & _ & Sx).
    exists g, x. repeat split; auto. rewrite Set'; auto. rewrite Sx; auto.
Qed.

End INPUT.

Lemma generate_input_glue_ddc_aux: input_glue_ddc m p.
Proof.
  destruct (generate_input_glue m p GEN) as (f & Ff & Fret & Fpar & Fvars & Fbody & _ & _).
  exists f. split; [apply gen_funct; auto|].
  intros mm GT.
  destruct (generate_externals m p GEN) as (_ & _ & _ & _ & _ & _ & Fu & _).
  destruct (gen_var _ _ Fu) as [bu Vu].
  destruct (GT _ _ _ Vu) as (u0 & Gu & Hu0). rewrite gen_types in Hu0.
  apply quiet_call_intro with (le := create_undef_temps (fn_temps f)); auto.
  - unfold function_entry. rewrite Fvars, Fpar. reflexivity.
  - intros CS ctx w.
    destruct (input_body mm bu GT Vu CS ctx w (create_undef_temps (fn_temps f)) u0 Gu Hu0)
      as (le' & mm' & u & X & G' & U & Hu & Rel).
    exists le', mm'. split.
    + rewrite Fbody. unfold gen_list_controller_expr_input_glue, gen_list_global_expr_input_glue.
      rewrite copies_map. exact X.
    + exists u. split; [exists bu, (Tstruct (nm_in_struct m)); auto|].
      rewrite gen_types. auto.
Qed.

(** ** Output glue *)

Section OUTPUT.

Variable tp : topic.
Hypothesis Htp : In tp (published m).
Local Notation c := (tp_cname tp).
Local Notation M := (tp_msg tp).

Variables (mm : mem) (b by_ : block) (y : mval).
Hypothesis GT : globals_typed p mm.
Hypothesis NG : not_global p b.
Hypothesis Vy : find_var ge (nm_out_var m) = Some (by_, Tstruct (nm_out_struct m)).
Hypothesis Gy : get_block mm by_ = Some (Tstruct (nm_out_struct m), y).
Hypothesis Hy : mval_has_type ce (Tstruct (nm_out_struct m)) y.

Let cmdE := deref_param command_param M.
Let le_ok (le : temp_env) : Prop := find_assoc command_param le = Some (Vptr b []).

Lemma output_le_ok_set: forall le q v, le_ok le -> le_ok (set_assoc (temp_name q) v le).
Proof.
  intros le q v H. unfold le_ok. rewrite find_assoc_set_other; auto.
  intros E; apply (proj2 (temp_name_not_param q)); auto.
Qed.

Lemma Nby: b <> by_.
Proof. intros E. apply (NG _ _ _ Vy); auto. Qed.

Lemma HM: In M (md_names msgs).
Proof. apply gen_msg_in. apply in_published in Htp; tauto. Qed.

(** Zeroing the leaves of [*command]. *)
Lemma exec_zeros:
  forall (CS : Type) (ctx : ros_context CS) (w : world CS) L le mm1 v1,
  le_ok le ->
  get_block mm1 b = Some (Tstruct M, v1) ->
  mval_shape v1 = undef_mval ce (Tstruct M) ->
  incl L (leaves msgs M) -> NoDup (map fst L) ->
  exists mm2 v2,
     exec_stmt ctx ge [] le mm1 w (seq_of (map (leaf_zero ce cmdE) L)) [] le mm2 w Out_normal
  /\ get_block mm2 b = Some (Tstruct M, v2)
  /\ mval_shape v2 = mval_shape v1
  /\ unchanged_except mm1 mm2 b
  /\ (forall lp q, In (lp, q) L -> mval_get v2 (path_steps lp) = Some (zero_mval ce (ctype_of_prim q)))
  /\ (forall p', (forall l, In l L -> path_disjoint (path_steps (fst l)) p') ->
        mval_get v2 p' = mval_get v1 p').
Proof.
  intros CS ctx w L; induction L as [|[lp q] L IH]; intros le mm1 v1 Hle G1 S1 Inc NDL.
  - exists mm1, v1. repeat split; auto. apply exec_Sskip. intros ? ? [].
  - assert (Hl: In (lp, q) (leaves msgs M)) by (apply Inc; simpl; auto).
    apply gen_leaf in Hl.
    destruct (eval_leaf m W ge [] le mm1 M lp q cmdE b [] Hl) as (A & T & _); auto.
    { apply eval_lvalue_deref_param; auto. }
    assert (Z: mval_get (zero_mval ce (Tstruct M)) (path_steps lp) = Some (zero_mval ce (ctype_of_prim q)))
      by (apply gen_zero_leaf; auto).
    assert (S1': mval_shape v1 = mval_shape (zero_mval ce (Tstruct M))) by (rewrite shape_zero_mval; auto).
    destruct (mval_get_same_shape _ _ _ _ (eq_sym S1') Z) as (x1 & Gx1 & Sx1).
    destruct (proj2 (mval_set_defined (path_steps lp) v1 (MVscalar (zero_val (ctype_of_prim q)))))
      as (v1' & Set1); eauto.
    set (mm1' := mkmem (pset b (Tstruct M, v1') (mem_contents mm1)) (mem_next mm1)).
    assert (St: store_path mm1 b (path_steps lp) (MVscalar (zero_val (ctype_of_prim q))) = Some mm1')
      by (unfold store_path; rewrite G1, Set1; auto).
    assert (G1': get_block mm1' b = Some (Tstruct M, v1')) by (unfold get_block; simpl; apply pgss).
    assert (Sh1: mval_shape v1' = mval_shape v1).
    { apply (mval_shape_set (path_steps lp) v1 (MVscalar (zero_val (ctype_of_prim q))) v1' x1 Gx1); auto.
      rewrite Sx1, zero_mval_prim. reflexivity. }
    inversion NDL as [|? ? Hnin NDL']; subst.
    destruct (IH le mm1' v1') as (mm2 & v2 & X & G2 & S2 & U2 & Z2 & K2); auto.
    { congruence. }
    { intros l Hl'; apply Inc; simpl; auto. }
    exists mm2, v2. repeat split; auto.
    + simpl. change (@nil event) with (@nil event ++ @nil event).
      eapply exec_Sseq_1; [|exact X]. unfold leaf_zero; simpl.
      rewrite app_nil_l in A. eapply exec_zero; eauto.
    + congruence.
    + destruct U2 as [U2n _]. rewrite U2n. reflexivity.
    + intros b' Nb'. destruct U2 as [_ U2o]. rewrite U2o by auto.
      unfold get_block; simpl. apply pgso; auto.
    + intros lp' q' [E|Hin].
      * inversion E; subst lp' q'. rewrite K2.
        { rewrite (mval_get_set_same _ _ _ _ Set1), zero_mval_prim; auto. }
        intros [lp2 q2] Hl2. simpl.
        apply (leaves_disjoint m lp2 lp (FTmsg M) q2 q).
        -- apply gen_leaf, Inc; simpl; auto.
        -- exact Hl.
        -- intros E2; subst lp2. apply Hnin. apply (in_map fst _ _ Hl2).
      * apply Z2; auto.
    + intros p' Dp. rewrite K2 by (intros; apply Dp; simpl; auto).
      eapply mval_get_set_disjoint; eauto. apply (Dp (lp, q)); simpl; auto.
Qed.

Let sv (o : outrel) : val := scalar_at y [Sfield (or_output o)].

Lemma output_source:
  forall o, In o (topic_outrels (make_tables m) c) ->
  exists q x,
     In o (nm_outrels m) /\ or_topic o = c
  /\ find_assoc (or_output o) (nm_outputs m) = Some q
  /\ resolve msgs (FTmsg M) (or_path o) = Some (FTprim q)
  /\ output_prim (make_tables m) (or_output o) = q
  /\ output_src m (make_tables m) o = Efield (Evar (nm_out_var m) (Tstruct (nm_out_struct m))) (or_output o) (ctype_of_prim q)
  /\ output_dst m M o = path_expr ce cmdE (or_path o)
  /\ mval_get y [Sfield (or_output o)] = Some (MVscalar x)
  /\ val_has_type x (ctype_of_prim q)
  /\ sv o = x.
Proof.
  intros o Ho.
  assert (Ht: In tp (nm_topics m)) by (apply in_published in Htp; tauto).
  destruct (output_exprs m tp o W Ht Ho) as (q & Hin & Ec & _ & O & R & Pq & Es & Ed).
  assert (T: type_at ce (Tstruct (nm_out_struct m)) [Sfield (or_output o)] = Some (ctype_of_prim q)).
  { cbn [type_at]. rewrite type_step_field, (field_type_outputs m W _ _ O). auto. }
  destruct (mval_get_has_type _ _ _ _ _ Hy T) as (xv & Gx & Hx).
  assert (Hs: exists x, xv = MVscalar x /\ val_has_type x (ctype_of_prim q)).
  { inversion Hx; eauto; destruct q; discriminate. }
  destruct Hs as (x & -> & Tx).
  exists q, x. repeat split; auto. unfold sv. apply scalar_at_spec; auto.
Qed.

Lemma output_item_ok:
  forall o, In o (topic_outrels (make_tables m) c) ->
  item_ok ge [] ce _ (fun o => output_prim (make_tables m) (or_output o)) (output_dst m M) (output_src m (make_tables m))
          (fun o => path_steps (or_path o)) sv le_ok mm b (Tstruct M) o.
Proof.
  intros o Ho.
  destruct (output_source o Ho) as (q & x & Hin & Ec & O & R & Pq & Es & Ed & Gx & Tx & Sx).
  unfold item_ok. rewrite Pq, Es, Ed, Sx. repeat split.
  - intros le mm1 _ [Fn Fo].
    rewrite (eval_expr_lvalue ge [] le mm1 (Efield _ _ _) I).
    erewrite eval_lvalue_field; [|reflexivity|eapply eval_lvalue_global_struct; eauto]. simpl.
    apply load_spec; [apply ctype_of_prim_scalar_type|].
    unfold load_path. rewrite Fo by (apply not_eq_sym, Nby). rewrite Gy. auto.
  - intros le mm1 Hle.
    destruct (eval_leaf m W ge [] le mm1 M (or_path o) q cmdE b [] R) as (A & _ & _); auto.
    apply eval_lvalue_deref_param; auto.
  - destruct (eval_leaf m W ge [] [(command_param, Vptr b [])] mm M (or_path o) q cmdE b [] R)
      as (_ & T & _); auto.
  - auto.
  - change (Tstruct M) with (ctype_of_ftype (FTmsg M)). rewrite type_at_ctype; auto.
    + rewrite R; reflexivity.
    + apply ftype_ok_msg, HM.
Qed.

(** What the zeroing and the copies leave in [*command]: a message of
    the topic's type, the related outputs in their fields, zero in every
    other leaf. *)
Definition base_value (mv : mval) : Prop :=
  mval_has_type ce (Tstruct M) mv
  /\ (forall o, In o (nm_outrels m) -> or_topic o = c ->
        exists v, mval_get y [Sfield (or_output o)] = Some (MVscalar v)
               /\ mval_get mv (path_steps (or_path o)) = Some (MVscalar v))
  /\ (forall lp q, resolve msgs (FTmsg M) lp = Some (FTprim q) ->
        (forall o, In o (nm_outrels m) -> or_topic o = c -> or_path o <> lp) ->
        mval_get mv (path_steps lp) = Some (zero_mval ce (ctype_of_prim q))).

Lemma output_body:
  forall (CS : Type) (ctx : ros_context CS) (w : world CS) le mv0,
  le_ok le ->
  get_block mm b = Some (Tstruct M, mv0) ->
  mval_shape mv0 = undef_mval ce (Tstruct M) ->
  exists le' mm' mv,
     exec_stmt ctx ge [] le mm w
       (Ssequence (seq_of (map (leaf_zero ce cmdE) (leaves msgs M)))
                  (seq_of (map (fun o => copy (output_prim (make_tables m) (or_output o)) (output_dst m M o) (output_src m (make_tables m) o))
                               (topic_outrels (make_tables m) c)))) [] le' mm' w Out_normal
  /\ le_ok le'
  /\ get_block mm' b = Some (Tstruct M, mv)
  /\ base_value mv
  /\ unchanged_except mm mm' b.
Proof.
  intros CS ctx w le mv0 Hle G0 S0.
  destruct (exec_zeros CS ctx w (leaves msgs M) le mm mv0 Hle G0 S0) as (mm1 & v1 & X1 & G1 & S1 & U1 & Z1 & _).
  { intros l; auto. }
  { apply leaves_nodup; auto. }
  set (z := zero_mval ce (Tstruct M)).
  assert (Hz: mval_has_type ce (Tstruct M) z) by (apply gen_zero_typed, HM).
  assert (Ez: v1 = z).
  { apply (leaves_ext m W M z v1 HM Hz).
    - unfold z. rewrite S1, S0, shape_zero_mval. auto.
    - intros lp q R. rewrite (Z1 lp q) by (apply leaves_spec; auto). unfold z.
      rewrite (gen_zero_leaf M lp q); auto. }
  subst v1.
  assert (Fr1: frame mm b mm1) by (destruct U1 as [U1n U1o]; split; auto).
  assert (ND1: NoDup (map (fun o => path_steps (or_path o)) (topic_outrels (make_tables m) c))).
  { rewrite <- (map_map or_path path_steps). apply NoDup_map_inj; [apply path_steps_inj|].
    apply wf_topic_outrels_paths_nodup; auto. }
  assert (DJ1: forall o1 o2, In o1 (topic_outrels (make_tables m) c) -> In o2 (topic_outrels (make_tables m) c) ->
                 path_steps (or_path o1) <> path_steps (or_path o2) ->
                 path_disjoint (path_steps (or_path o1)) (path_steps (or_path o2))).
  { intros o1 o2 H1 H2 N.
    destruct (output_source o1 H1) as (q1 & _ & _ & _ & _ & R1 & _).
    destruct (output_source o2 H2) as (q2 & _ & _ & _ & _ & R2 & _).
    apply (leaves_disjoint m _ _ (FTmsg M) q1 q2 R1 R2). congruence. }
  destruct (exec_copies ctx ge [] w ce _ (fun o => output_prim (make_tables m) (or_output o)) (output_dst m M) (output_src m (make_tables m))
              (fun o => path_steps (or_path o)) sv le_ok output_le_ok_set mm b (Tstruct M)
              (topic_outrels (make_tables m) c) le mm1 z Hle Fr1 G1 Hz output_item_ok ND1 DJ1)
    as (le' & mm' & mv & X2 & Hle' & Fr & G' & Hmv & Set' & Keep').
  exists le', mm', mv. split; [|split; [auto|split; [auto|split]]].
    + change (@nil event) with (@nil event ++ @nil event). eapply exec_Sseq_1; eauto.
    + split; [exact Hmv|split].
      * intros o Ho Eo.
        assert (Ho': In o (topic_outrels (make_tables m) c)).
        { apply In_topic_outrels; auto. }
        destruct (output_source o Ho') as (q & x & _ & _ & _ & _ & _ & _ & _ & Gx & _ & Sx).
        exists x. split; auto. rewrite Set'; auto. rewrite Sx; auto.
      * intros lp q R NF. rewrite Keep'.
        { unfold z. apply gen_zero_leaf; auto. }
        intros o Ho. destruct (output_source o Ho) as (q' & _ & Hin & Ec & _ & R' & _).
        apply (leaves_disjoint m _ _ (FTmsg M) q' q R' R). apply NF; auto.
    + destruct Fr as [Fn Fo]. split; auto.
Qed.

(** The stamp: [_t_uint = ros_time_sec(); command->sp.sec = _t_uint;]
    and the same for [nsec]. *)
Lemma exec_time_call:
  forall (CS : Type) (ctx : ros_context CS) (w : world CS) le mm1 f ef x,
  find_def p f = Some (Gfun (External ef [] tuint)) ->
  (forall mm0, external_call ctx ge ef [] mm0 w = Some (Vint x, [], mm0, w)) ->
  exec_stmt ctx ge [] le mm1 w (time_call f) [] (set_assoc (temp_name Puint32) (Vint x) le) mm1 w Out_normal.
Proof.
  intros CS ctx w le mm1 f ef x F EC.
  change (set_assoc (temp_name Puint32) (Vint x) le) with (set_opttemp (Some (temp_name Puint32)) (Vint x) le).
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

Lemma exec_assign_uint:
  forall (CS : Type) (ctx : ros_context CS) (w : world CS) le mm1 v1 lp x,
  le_ok le -> find_assoc (temp_name Puint32) le = Some (Vint x) ->
  norm_int I32 Unsigned x = x ->
  resolve msgs (FTmsg M) lp = Some (FTprim Puint32) ->
  get_block mm1 b = Some (Tstruct M, v1) -> mval_has_type ce (Tstruct M) v1 ->
  exists mm2 v2,
     exec_stmt ctx ge [] le mm1 w (Sassign (path_expr ce cmdE lp) (Etempvar (temp_name Puint32) tuint))
               [] le mm2 w Out_normal
  /\ get_block mm2 b = Some (Tstruct M, v2) /\ mval_has_type ce (Tstruct M) v2
  /\ mval_set v1 (path_steps lp) (MVscalar (Vint x)) = Some v2
  /\ mem_next mm2 = mem_next mm1 /\ (forall b', b' <> b -> get_block mm2 b' = get_block mm1 b').
Proof.
  intros CS ctx w le mm1 v1 lp x Hle Tx Nx R G1 H1.
  destruct (eval_leaf m W ge [] le mm1 M lp Puint32 cmdE b [] R) as (L & T & _); auto.
  { apply eval_lvalue_deref_param; auto. }
  assert (Tp: type_at ce (Tstruct M) (path_steps lp) = Some (ctype_of_prim Puint32)).
  { change (Tstruct M) with (ctype_of_ftype (FTmsg M)). rewrite type_at_ctype; auto.
    - rewrite R; reflexivity.
    - apply ftype_ok_msg. eapply resolve_leaf_msg; eauto. }
  assert (Hx: mval_has_type ce (ctype_of_prim Puint32) (MVscalar (Vint x))) by (constructor; auto).
  destruct (store_typed ce mm1 b (Tstruct M) v1 (path_steps lp) _ _ G1 H1 Tp Hx)
    as (mm2 & v2 & S & Sv & G2 & H2 & N2 & O2).
  exists mm2, v2. repeat split; auto.
  apply exec_Sassign.
  rewrite (eval_assign_scalar ge [] le mm1 _ _ b ([] ++ path_steps lp) (Vint x) L).
  - rewrite T. unfold store. rewrite sem_cast_same by exact Nx. exact S.
  - rewrite T. reflexivity.
  - exact Tx.
Qed.

Lemma time_sec_norm: forall t, norm_int I32 Unsigned (time_sec t) = time_sec t.
Proof. intros; unfold time_sec; apply norm_int_idem. Qed.
Lemma time_nsec_norm: forall t, norm_int I32 Unsigned (time_nsec t) = time_nsec t.
Proof. intros; unfold time_nsec; apply norm_int_idem. Qed.

Lemma stamp_run:
  forall (CS : Type) (ctx : ros_context CS) (w : world CS) le mm1 v1 sp,
  le_ok le -> topic_stamp m c = Some sp ->
  get_block mm1 b = Some (Tstruct M, v1) -> mval_has_type ce (Tstruct M) v1 ->
  exists le' mm2 v2,
     exec_stmt ctx ge [] le mm1 w (stamp_stmts m M sp) [] le' mm2 w Out_normal
  /\ get_block mm2 b = Some (Tstruct M, v2) /\ mval_has_type ce (Tstruct M) v2
  /\ mem_next mm2 = mem_next mm1 /\ (forall b', b' <> b -> get_block mm2 b' = get_block mm1 b')
  /\ mval_get v2 (path_steps (sp ++ [PField "sec"%string])) = Some (MVscalar (Vint (time_sec (w_time w))))
  /\ mval_get v2 (path_steps (sp ++ [PField "nsec"%string])) = Some (MVscalar (Vint (time_nsec (w_time w))))
  /\ (forall p', path_disjoint (path_steps (sp ++ [PField "sec"%string])) p' ->
                  path_disjoint (path_steps (sp ++ [PField "nsec"%string])) p' ->
                  mval_get v2 p' = mval_get v1 p').
Proof.
  intros CS ctx w le mm1 v1 sp Hle ST G1 H1.
  destruct (wf_stamp m tp sp W Htp ST) as (Rs & Rn & _).
  assert (NE: nm_stamps m <> []).
  { unfold topic_stamp in ST. intros E; rewrite E in ST; discriminate. }
  destruct (generate_time_externals m p GEN NE) as [Fs Fn].
  set (le1 := set_assoc (temp_name Puint32) (Vint (time_sec (w_time w))) le).
  assert (Hle1: le_ok le1) by (apply output_le_ok_set; auto).
  destruct (exec_assign_uint CS ctx w le1 mm1 v1 _ _ Hle1 (find_assoc_set_same _ _ _ _)
              (time_sec_norm _) Rs G1 H1) as (mm2 & v2 & X2 & G2 & H2 & S2 & N2 & O2).
  set (le2 := set_assoc (temp_name Puint32) (Vint (time_nsec (w_time w))) le1).
  assert (Hle2: le_ok le2) by (apply output_le_ok_set; auto).
  destruct (exec_assign_uint CS ctx w le2 mm2 v2 _ _ Hle2 (find_assoc_set_same _ _ _ _)
              (time_nsec_norm _) Rn G2 H2) as (mm3 & v3 & X3 & G3 & H3 & S3 & N3 & O3).
  assert (Dsn: path_disjoint (path_steps (sp ++ [PField "sec"%string])) (path_steps (sp ++ [PField "nsec"%string]))).
  { apply (leaves_disjoint m _ _ (FTmsg M) Puint32 Puint32 Rs Rn).
    intros E. apply app_inv_head in E. discriminate. }
  exists le2, mm3, v3. repeat split; auto.
  - unfold stamp_stmts, seq_of. simpl fold_right.
    change (@nil event) with (@nil event ++ @nil event ++ @nil event ++ @nil event ++ @nil event).
    eapply exec_Sseq_1; [eapply exec_time_call; [exact Fs | reflexivity]|].
    eapply exec_Sseq_1; [exact X2|].
    eapply exec_Sseq_1; [eapply exec_time_call; [exact Fn | reflexivity]|].
    eapply exec_Sseq_1; [exact X3|]. apply exec_Sskip.
  - congruence.
  - intros b' N. rewrite O3, O2; auto.
  - rewrite (mval_get_set_disjoint _ _ _ _ _ (path_disjoint_sym _ _ Dsn) S3).
    eapply mval_get_set_same; eauto.
  - eapply mval_get_set_same; eauto.
  - intros p' D1 D2. rewrite (mval_get_set_disjoint _ _ _ _ _ D2 S3).
    apply (mval_get_set_disjoint _ _ _ _ _ D1 S2).
Qed.

End OUTPUT.

Lemma generate_output_glue_ddc_aux:
  forall tp, In tp (published m) -> output_glue_ddc m p tp.
Proof.
  intros tp Htp.
  destruct (generate_output_glue m p tp GEN Htp) as (f & Ff & Fret & Fpar & Fvars & Fbody & _ & _ & _).
  exists f. split; [apply gen_funct; auto|].
  intros mm b mv0 y GT NG G0 S0 GV.
  rewrite gen_types in S0.
  destruct (generate_externals m p GEN) as (_ & _ & _ & _ & _ & _ & _ & Fy).
  destruct (gen_var _ _ Fy) as [by_ Vy].
  destruct (GT _ _ _ Vy) as (y' & Gy & Hy). rewrite gen_types in Hy.
  unfold global_value in GV. rewrite Vy, Gy in GV. inversion GV; subst y'.
  set (le0 := set_assoc command_param (Vptr b []) (create_undef_temps (fn_temps f))).
  apply quiet_call_at_intro with (le := le0); auto.
  - unfold function_entry. rewrite Fvars, Fpar. reflexivity.
  - intros CS ctx w.
    destruct (output_body tp Htp mm b by_ y NG Vy Gy Hy CS ctx w le0 mv0)
      as (le' & mm' & mv & X & Hle' & G' & [Tm [Rel Zero]] & [U1 U2]); auto.
    { unfold le0. apply find_assoc_set_same. }
    assert (Xb: exec_stmt ctx ge [] le0 mm w (output_base m tp) [] le' mm' w Out_normal).
    { unfold output_base, gen_list_message_expr_output_glue, gen_list_controller_expr_output_glue.
      rewrite copies_map. exact X. }
    assert (Htop: In tp (nm_topics m)) by (apply in_published in Htp; tauto).
    assert (FT: find_topic (nm_topics m) (tp_cname tp) = Some tp)
      by (apply In_find_topic; [apply (wf_cnames_nodup m W)|auto]).
    assert (ROUT: forall o, In o (nm_outrels m) -> or_topic o = tp_cname tp ->
                  exists q, resolve msgs (FTmsg (tp_msg tp)) (or_path o) = Some (FTprim q)).
    { intros o Ho Eo. destruct (wf_outrel m o W Ho) as (tp' & q & Ft & _ & _ & R).
      rewrite Eo, FT in Ft. inversion Ft; subst tp'. eauto. }
    destruct (topic_stamp m (tp_cname tp)) as [sp|] eqn:ST.
    + destruct (stamp_run tp Htp b CS ctx w le' mm' mv sp Hle' ST G' Tm)
        as (le2 & mm2 & v2 & X2 & G2 & H2 & N2 & O2 & Gs & Gn & Keep).
      destruct (wf_stamp m tp sp W Htp ST) as (Rs & Rn & NO).
      assert (DJ: forall lp q, resolve msgs (FTmsg (tp_msg tp)) lp = Some (FTprim q) ->
                  lp <> sp ++ [PField "sec"%string] -> lp <> sp ++ [PField "nsec"%string] ->
                  mval_get v2 (path_steps lp) = mval_get mv (path_steps lp)).
      { intros lp q R N1 N2'. apply Keep.
        - apply (leaves_disjoint m _ _ (FTmsg (tp_msg tp)) Puint32 q Rs R). auto.
        - apply (leaves_disjoint m _ _ (FTmsg (tp_msg tp)) Puint32 q Rn R). auto. }
      exists le2, mm2. split.
      * rewrite Fbody. change (@nil event) with (@nil event ++ @nil event). eapply exec_Sseq_1; eauto.
      * exists v2. split; [auto|split].
        -- split; [exact H2|split; [|split]].
           ++ intros o Ho Eo. destruct (Rel o Ho Eo) as (v & Yv & Mv). exists v. split; auto.
              destruct (ROUT o Ho Eo) as (q & R). rewrite DJ with (q := q); auto;
                intros E; apply (NO o _ Ho Eo E).
           ++ intros sp' E. unfold topic_stamp in ST. rewrite ST in E. inversion E; subst sp'. auto.
           ++ intros lp q R NOUT NS. destruct (NS sp ST) as [N1 N2']. rewrite DJ with (q := q); auto.
        -- split; [congruence|]. intros b' Nb. rewrite O2, U2; auto.
    + exists le', mm'. split; [rewrite Fbody; exact Xb|].
      exists mv. split; [auto|split; [|split; auto]].
      split; [exact Tm|split; [exact Rel|split]].
      * intros sp E. unfold topic_stamp in ST. rewrite ST in E. discriminate.
      * intros lp q R NOUT _. apply Zero; auto.
Qed.

End GENERATED.

(** ** The theorems *)

(** T1 for callbacks (the paper's Figure 10, for every model). *)
Theorem generate_callback_ddc:
  forall m p, generate m = OK p ->
  forall tp, In tp (subscribed m) -> callback_ddc m p tp.
Proof. intros m p GEN; apply generate_callback_ddc_aux; auto. Qed.

(** T1 for [input_glue] (the paper's Figure 12, for every model). *)
Theorem generate_input_glue_ddc:
  forall m p, generate m = OK p -> input_glue_ddc m p.
Proof. intros m p GEN; apply generate_input_glue_ddc_aux; auto. Qed.

(** T1 for the output glue of every published topic. *)
Theorem generate_output_glue_ddc:
  forall m p, generate m = OK p ->
  forall tp, In tp (published m) -> output_glue_ddc m p tp.
Proof. intros m p GEN; apply generate_output_glue_ddc_aux; auto. Qed.
