(** * T1 for the output glue *)

(** For every well-formed node model [m] and its program [p]
    ([generate m = OK p]), the output glue of every published topic meets
    [DDC.output_glue_ddc]: the zeroing of the message, the copies of the
    output relations, the stamp (rule 4.13) and the constant strings
    (rule 4.14).  The theorem is stated in [Glueproof]. *)

From Coq Require Import String List ZArith Bool Lia.
From ROSGen Require Import Errors Maps Syntax Values Operators Memory Environment Semantics NodeModel Wellformed Generator Generatorspec Stampspec Generatorproof.
From ROSGen Require Import DDC Copyproof.
From ROSGen Require Import Gluefacts Inputproof.
Import ListNotations.

Local Open Scope list_scope.

Section GENERATED.

Variable m : node_model.
Variable p : program.
Hypothesis GEN : generate m = OK p.

Let W : wf_facts m := wf_facts_intro m (generate_sound m p GEN).
Let ND : NoDup (map fst (prog_defs p)) := generate_names_distinct m p GEN.

Local Notation ge := (globalenv p).
Local Notation ce := (composites m).
Local Notation msgs := (nm_msgs m).

(** The lemmas of [Gluefacts] on this program (its section's variables given). *)
Local Notation gen_types := (Gluefacts.gen_types m p GEN) (only parsing).
Local Notation gen_funct := (Gluefacts.gen_funct m p GEN) (only parsing).
Local Notation gen_var := (Gluefacts.gen_var m p GEN) (only parsing).
Local Notation gen_msg_in := (Gluefacts.gen_msg_in m p GEN) (only parsing).
Local Notation gen_leaf := (Gluefacts.gen_leaf m p GEN) (only parsing).
Local Notation gen_zero_typed := (Gluefacts.gen_zero_typed m p GEN) (only parsing).
Local Notation gen_zero_leaf := (Gluefacts.gen_zero_leaf m p GEN) (only parsing).
Local Notation exec_call0_external := (Gluefacts.exec_call0_external m p GEN) (only parsing).

(** The lemmas of [Inputproof] on this program (its section's variables given). *)
Local Notation eval_ctrl_leaf := (Inputproof.eval_ctrl_leaf m p GEN) (only parsing).
Local Notation eval_const_of := (Inputproof.eval_const_of p) (only parsing).

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

Let sv (o : outrel) : val := scalar_at y (Sfield (or_output o) :: path_steps (or_elem o)).

Lemma output_source:
  forall o, In o (topic_outrels (make_tables m) c) ->
  exists t q x,
     In o (nm_outrels m) /\ or_topic o = c
  /\ find_assoc (or_output o) (nm_outputs m) = Some t
  /\ ctrl_ftype_ok t = true
  /\ ctrl_prim t (or_elem o) = Some q
  /\ resolve msgs (FTmsg M) (or_path o) = Some (FTprim q)
  /\ outrel_prim (make_tables m) o = q
  /\ output_src m o = path_expr ce (Evar (nm_out_var m) (Tstruct (nm_out_struct m))) (PField (or_output o) :: or_elem o)
  /\ output_dst m M o = path_expr ce cmdE (or_path o)
  /\ mval_get y (Sfield (or_output o) :: path_steps (or_elem o)) = Some (MVscalar x)
  /\ val_has_type x (ctype_of_prim q)
  /\ sv o = x.
Proof.
  intros o Ho.
  assert (Ht: In tp (nm_topics m)) by (apply in_published in Htp; tauto).
  destruct (output_exprs m tp o W Ht Ho) as (t & q & Hin & Ec & _ & O & Q & R & Pq & Es & Ed).
  assert (OKt: ctrl_ftype_ok t = true) by (apply (wf_outputs_ok m W (or_output o, t)); apply find_assoc_In; auto).
  destruct (ctrl_leaf_resolve msgs (md_names msgs) t (or_elem o) q OKt Q) as [Ft Rt].
  assert (T: type_at ce (Tstruct (nm_out_struct m)) (Sfield (or_output o) :: path_steps (or_elem o)) = Some (ctype_of_prim q)).
  { cbn [type_at]. rewrite type_step_field, (field_type_outputs m W _ _ O).
    rewrite (type_at_ctype m W); auto. rewrite Rt; auto. }
  destruct (mval_get_has_type _ _ _ _ _ Hy T) as (xv & Gx & Hx).
  assert (Hs: exists x, xv = MVscalar x /\ val_has_type x (ctype_of_prim q)).
  { inversion Hx; eauto; destruct q; discriminate. }
  destruct Hs as (x & -> & Tx).
  exists t, q, x. repeat split; auto. unfold sv. apply scalar_at_spec; auto.
Qed.

Lemma output_item_ok:
  forall o, In o (topic_outrels (make_tables m) c) ->
  item_ok ge [] ce _ (fun o => outrel_prim (make_tables m) o) (output_dst m M) (output_src m)
          (fun o => path_steps (or_path o)) sv le_ok mm b (Tstruct M) o.
Proof.
  intros o Ho.
  destruct (output_source o Ho) as (t & q & x & Hin & Ec & O & OKt & Q & R & Pq & Es & Ed & Gx & Tx & Sx).
  unfold item_ok. rewrite Pq, Es, Ed, Sx. repeat split.
  - intros le mm1 _ [Fn Fo].
    destruct (eval_ctrl_leaf ge [] le mm1 (nm_out_var m) (or_output o) t (or_elem o) q (nm_out_struct m) by_
                OKt Q (field_type_outputs m W _ _ O)) as (_ & _ & EV).
    { eapply eval_lvalue_global_struct; eauto. }
    rewrite EV. apply load_spec; [apply ctype_of_prim_scalar_type|].
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
        exists v, mval_get y (Sfield (or_output o) :: path_steps (or_elem o)) = Some (MVscalar v)
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
                  (seq_of (map (fun o => copy (outrel_prim (make_tables m) o) (output_dst m M o) (output_src m o))
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
    destruct (output_source o1 H1) as (t1 & q1 & _ & _ & _ & _ & _ & _ & R1 & _).
    destruct (output_source o2 H2) as (t2 & q2 & _ & _ & _ & _ & _ & _ & R2 & _).
    apply (leaves_disjoint m _ _ (FTmsg M) q1 q2 R1 R2). congruence. }
  destruct (exec_copies ctx ge [] w ce _ (fun o => outrel_prim (make_tables m) o) (output_dst m M) (output_src m)
              (fun o => path_steps (or_path o)) sv le_ok output_le_ok_set mm b (Tstruct M)
              (topic_outrels (make_tables m) c) le mm1 z Hle Fr1 G1 Hz output_item_ok ND1 DJ1)
    as (le' & mm' & mv & X2 & Hle' & Fr & G' & Hmv & Set' & Keep').
  exists le', mm', mv. split; [|split; [auto|split; [auto|split]]].
    + change (@nil event) with (@nil event ++ @nil event). eapply exec_Sseq_1; eauto.
    + split; [exact Hmv|split].
      * intros o Ho Eo.
        assert (Ho': In o (topic_outrels (make_tables m) c)).
        { apply In_topic_outrels; auto. }
        destruct (output_source o Ho') as (t & q & x & _ & _ & _ & _ & _ & _ & _ & _ & _ & Gx & _ & Sx).
        exists x. split; auto. rewrite Set'; auto. rewrite Sx; auto.
      * intros lp q R NF. rewrite Keep'.
        { unfold z. apply gen_zero_leaf; auto. }
        intros o Ho. destruct (output_source o Ho) as (t' & q' & _ & Hin & Ec & _ & _ & _ & R' & _).
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
  intros CS ctx w le mm1 f ef x F EC. apply (exec_call0_external CS ctx w le mm1 f ef); auto.
Qed.

Lemma exec_assign_leaf:
  forall (CS : Type) (ctx : ros_context CS) (w : world CS) le mm1 v1 lp q rhs v,
  le_ok le -> eval_expr ge [] le mm1 rhs = Some v ->
  val_has_type v (ctype_of_prim q) ->
  resolve msgs (FTmsg M) lp = Some (FTprim q) ->
  get_block mm1 b = Some (Tstruct M, v1) -> mval_has_type ce (Tstruct M) v1 ->
  exists mm2 v2,
     exec_stmt ctx ge [] le mm1 w (Sassign (path_expr ce cmdE lp) rhs) [] le mm2 w Out_normal
  /\ get_block mm2 b = Some (Tstruct M, v2) /\ mval_has_type ce (Tstruct M) v2
  /\ mval_set v1 (path_steps lp) (MVscalar v) = Some v2
  /\ mem_next mm2 = mem_next mm1 /\ (forall b', b' <> b -> get_block mm2 b' = get_block mm1 b').
Proof.
  intros CS ctx w le mm1 v1 lp q rhs v Hle Ev Nv R G1 H1.
  destruct (eval_leaf m W ge [] le mm1 M lp q cmdE b [] R) as (L & T & _); auto.
  { apply eval_lvalue_deref_param; auto. }
  assert (Tp: type_at ce (Tstruct M) (path_steps lp) = Some (ctype_of_prim q)).
  { change (Tstruct M) with (ctype_of_ftype (FTmsg M)). rewrite type_at_ctype; auto.
    - rewrite R; reflexivity.
    - apply ftype_ok_msg. eapply resolve_leaf_msg; eauto. }
  assert (Hx: mval_has_type ce (ctype_of_prim q) (MVscalar v))
    by (apply mht_scalar; auto; apply ctype_of_prim_scalar_type).
  destruct (store_typed ce mm1 b (Tstruct M) v1 (path_steps lp) _ _ G1 H1 Tp Hx)
    as (mm2 & v2 & S & Sv & G2 & H2 & N2 & O2).
  exists mm2, v2. repeat split; auto.
  apply exec_Sassign.
  rewrite (eval_assign_scalar ge [] le mm1 _ _ b ([] ++ path_steps lp) v L).
  - rewrite T. unfold store. rewrite sem_cast_same by exact Nv. exact S.
  - rewrite T. apply ctype_of_prim_scalar_type.
  - exact Ev.
Qed.

Lemma time_sec_norm: forall t, norm_int I32 Unsigned (time_sec t) = time_sec t.
Proof. intros; unfold time_sec; apply norm_int_idem. Qed.
Lemma time_nsec_norm: forall t, norm_int I32 Unsigned (time_nsec t) = time_nsec t.
Proof. intros; unfold time_nsec; apply norm_int_idem. Qed.

(** The seconds of the time, read from [_t_uint], as the stamp's [sec]
    takes them: themselves on ROS 1, converted to [int] on ROS 2. *)
Lemma eval_stamp_sec:
  forall le mmx t, find_assoc (temp_name Puint32) le = Some (Vint (time_sec t)) ->
     eval_expr ge [] le mmx (stamp_sec_expr m) = Some (Vint (stamp_sec m t))
  /\ val_has_type (Vint (stamp_sec m t)) (ctype_of_prim (time_sec_prim msgs)).
Proof.
  intros le mmx t Tx. unfold stamp_sec_expr, stamp_sec, time_sec_prim.
  destruct (time_is_ros2 msgs); cbn [eval_expr]; rewrite Tx; split; auto.
  - apply norm_int_idem.
  - apply time_sec_norm.
Qed.

Lemma stamp_nsec_not_sec: stamp_nsec m <> "sec"%string.
Proof. unfold stamp_nsec, time_nsec_field. destruct (time_is_ros2 msgs); discriminate. Qed.

Lemma stamp_run:
  forall (CS : Type) (ctx : ros_context CS) (w : world CS) le mm1 v1 sp,
  le_ok le -> topic_stamp m c = Some sp ->
  (forall b', b' <> b -> get_block mm1 b' = get_block mm b') ->
  get_block mm1 b = Some (Tstruct M, v1) -> mval_has_type ce (Tstruct M) v1 ->
  exists le' mm2 v2,
     exec_stmt ctx ge [] le mm1 w (stamp_stmts m (make_tables m) c M sp) [] le' mm2 w Out_normal
  /\ le_ok le'
  /\ get_block mm2 b = Some (Tstruct M, v2) /\ mval_has_type ce (Tstruct M) v2
  /\ mem_next mm2 = mem_next mm1 /\ (forall b', b' <> b -> get_block mm2 b' = get_block mm1 b')
  /\ match find_assoc c (nm_stamp_from m) with
     | None =>
         mval_get v2 (path_steps (sp ++ [PField "sec"%string])) = Some (MVscalar (Vint (stamp_sec m (w_time w))))
      /\ mval_get v2 (path_steps (sp ++ [PField (stamp_nsec m)])) = Some (MVscalar (Vint (time_nsec (w_time w))))
     | Some (s0, sp') =>
         mval_get v2 (path_steps (sp ++ [PField "sec"%string]))
         = mval_get (global_msg p mm s0) (path_steps (sp' ++ [PField "sec"%string]))
      /\ mval_get v2 (path_steps (sp ++ [PField (stamp_nsec m)]))
         = mval_get (global_msg p mm s0) (path_steps (sp' ++ [PField (stamp_nsec m)]))
     end
  /\ (forall p', path_disjoint (path_steps (sp ++ [PField "sec"%string])) p' ->
                  path_disjoint (path_steps (sp ++ [PField (stamp_nsec m)])) p' ->
                  mval_get v2 p' = mval_get v1 p').
Proof.
  intros CS ctx w le mm1 v1 sp Hle ST Fr1 G1 H1.
  destruct (wf_stamp m tp sp W Htp ST) as (Rs & Rn & _).
  assert (Dsn: path_disjoint (path_steps (sp ++ [PField "sec"%string])) (path_steps (sp ++ [PField (stamp_nsec m)]))).
  { apply (leaves_disjoint m _ _ (FTmsg M) _ Puint32 Rs Rn).
    intros E. apply app_inv_head in E. inversion E as [E1]. apply stamp_nsec_not_sec; auto. }
  unfold stamp_stmts. fold (topic_stamp_from m c). fold (stamp_nsec m).
  destruct (topic_stamp_from m c) as [[s0 sp']|] eqn:SF; unfold topic_stamp_from in SF.
  - (* copied from the subscribed topic [s0] *)
    assert (Hin: In (c, (s0, sp')) (nm_stamp_from m)) by (apply find_assoc_In; auto).
    destruct (wf_stamp_from m _ _ _ W Hin) as (tp' & Ft & Sub & Rs' & Rn' & _).
    destruct (find_topic_In _ _ _ Ft) as [Htop' Ec].
    assert (Hs': In tp' (subscribed m)).
    { apply in_subscribed. split; auto. unfold is_subscribed in Sub. destruct (tp_dir tp'); [auto|discriminate]. }
    destruct (generate_callback m p tp' GEN Hs') as [Fv _]. rewrite Ec in Fv.
    destruct (gen_var _ _ Fv) as [bg Vg].
    destruct (GT _ _ _ Vg) as (g & Gg & Hg). rewrite gen_types in Hg.
    assert (Nbg: bg <> b) by (intros E; apply (NG _ _ _ Vg); auto).
    assert (GM: global_msg p mm s0 = g) by (unfold global_msg, global_value; rewrite Vg, Gg; auto).
    rewrite GM, (topic_msg_tables m _ _ Ft).
    destruct (leaf_typed m W _ _ _ g Rs' Hg) as (xs & Gxs & Txs).
    destruct (leaf_typed m W _ _ _ g Rn' Hg) as (xn & Gxn & Txn).
    assert (SRC: forall mmx f q x, (forall b', b' <> b -> get_block mmx b' = get_block mm b') ->
                 resolve msgs (FTmsg (tp_msg tp')) (sp' ++ [PField f]) = Some (FTprim q) ->
                 mval_get g (path_steps (sp' ++ [PField f])) = Some (MVscalar x) ->
                 forall lex, eval_expr ge [] lex mmx
                          (path_expr ce (Evar (msg_var s0) (Tstruct (tp_msg tp'))) (sp' ++ [PField f])) = Some x).
    { intros mmx f q x Frx R Gx lex.
      destruct (eval_leaf m W ge [] lex mmx (tp_msg tp') (sp' ++ [PField f]) q
                  (Evar (msg_var s0) (Tstruct (tp_msg tp'))) bg [] R) as (_ & _ & E); auto.
      { eapply eval_lvalue_global_struct; eauto. }
      rewrite E. apply load_spec; [apply ctype_of_prim_scalar_type|].
      unfold load_path. rewrite Frx by auto. rewrite Gg. auto. }
    set (le1 := set_assoc (temp_name (time_sec_prim msgs)) xs le).
    assert (Hle1: le_ok le1) by (apply output_le_ok_set; auto).
    destruct (exec_assign_leaf CS ctx w le1 mm1 v1 _ _ (Etempvar (temp_name (time_sec_prim msgs))
                (ctype_of_prim (time_sec_prim msgs))) xs Hle1 (find_assoc_set_same _ _ _ _)
                Txs Rs G1 H1) as (mm2 & v2 & X2 & G2 & H2 & S2 & N2 & O2).
    set (le2 := set_assoc (temp_name Puint32) xn le1).
    assert (Hle2: le_ok le2) by (apply output_le_ok_set; auto).
    destruct (exec_assign_leaf CS ctx w le2 mm2 v2 _ _ (Etempvar (temp_name Puint32) (ctype_of_prim Puint32))
                xn Hle2 (find_assoc_set_same _ _ _ _) Txn Rn G2 H2) as (mm3 & v3 & X3 & G3 & H3 & S3 & N3 & O3).
    exists le2, mm3, v3. unfold stamp_nsec in *. repeat split; auto.
    + unfold seq_of. simpl fold_right.
      change (@nil event) with (@nil event ++ (@nil event ++ @nil event)).
      eapply exec_Sseq_1; [|eapply exec_Sseq_1; [|apply exec_Sskip]].
      * unfold copy. change (@nil event) with (@nil event ++ @nil event). eapply exec_Sseq_1; [|exact X2].
        apply exec_Sset. eapply SRC; eauto.
      * unfold copy. change (@nil event) with (@nil event ++ @nil event). eapply exec_Sseq_1; [|exact X3].
        apply exec_Sset. eapply SRC; eauto.
        intros b' N. rewrite O2 by auto. auto.
    + congruence.
    + intros b' N. rewrite O3, O2; auto.
    + rewrite (mval_get_set_disjoint _ _ _ _ _ (path_disjoint_sym _ _ Dsn) S3).
      rewrite (mval_get_set_same _ _ _ _ S2). auto.
    + rewrite (mval_get_set_same _ _ _ _ S3). auto.
    + intros p' D1 D2. rewrite (mval_get_set_disjoint _ _ _ _ _ D2 S3).
      apply (mval_get_set_disjoint _ _ _ _ _ D1 S2).
  - (* the cycle's time *)
    assert (NE: nm_stamps m <> []).
    { unfold topic_stamp in ST. intros E; rewrite E in ST; discriminate. }
    destruct (generate_time_externals m p GEN NE) as [Fs Fn].
    set (le1 := set_assoc (temp_name Puint32) (Vint (time_sec (w_time w))) le).
    assert (Hle1: le_ok le1) by (apply output_le_ok_set; auto).
    destruct (eval_stamp_sec le1 mm1 (w_time w) (find_assoc_set_same _ _ _ _)) as [Es Ts].
    destruct (exec_assign_leaf CS ctx w le1 mm1 v1 _ _ _ _ Hle1 Es Ts Rs G1 H1)
      as (mm2 & v2 & X2 & G2 & H2 & S2 & N2 & O2).
    set (le2 := set_assoc (temp_name Puint32) (Vint (time_nsec (w_time w))) le1).
    assert (Hle2: le_ok le2) by (apply output_le_ok_set; auto).
    destruct (exec_assign_leaf CS ctx w le2 mm2 v2 _ Puint32 (Etempvar (temp_name Puint32) tuint) _ Hle2
                (find_assoc_set_same _ _ _ _) (time_nsec_norm _) Rn G2 H2) as (mm3 & v3 & X3 & G3 & H3 & S3 & N3 & O3).
    exists le2, mm3, v3. unfold stamp_nsec in *. repeat split; auto.
    + unfold seq_of. simpl fold_right.
      change (@nil event) with (@nil event ++ @nil event ++ @nil event ++ @nil event ++ @nil event).
      eapply exec_Sseq_1; [eapply exec_time_call; [exact Fs | reflexivity]|].
      eapply exec_Sseq_1; [exact X2|].
      eapply exec_Sseq_1; [eapply exec_time_call; [exact Fn | reflexivity]|].
      eapply exec_Sseq_1; [exact X3|]. apply exec_Sskip.
    + congruence.
    + intros b' N. rewrite O3, O2; auto.
    + rewrite (mval_get_set_disjoint _ _ _ _ _ (path_disjoint_sym _ _ Dsn) S3).
      eapply mval_get_set_same; eauto.
    + eapply mval_get_set_same; eauto.
    + intros p' D1 D2. rewrite (mval_get_set_disjoint _ _ _ _ _ D2 S3).
      apply (mval_get_set_disjoint _ _ _ _ _ D1 S2).
Qed.

(** The constant strings: [command->sp.len = n; command->sp.data[i] = b;]
    for a list of stores at leaves, each path once. *)
Lemma exec_const_stores:
  forall (CS : Type) (ctx : ros_context CS) (w : world CS) L le mm1 v1,
  le_ok le ->
  get_block mm1 b = Some (Tstruct M, v1) -> mval_has_type ce (Tstruct M) v1 ->
  (forall a, In a L -> resolve msgs (FTmsg M) (fst (fst a)) = Some (FTprim (snd (fst a)))
                     /\ val_has_type (Vint (snd a)) (ctype_of_prim (snd (fst a)))) ->
  NoDup (map (fun a => fst (fst a)) L) ->
  exists mm2 v2,
     exec_stmt ctx ge [] le mm1 w (seq_of (map (const_store m M) L)) [] le mm2 w Out_normal
  /\ get_block mm2 b = Some (Tstruct M, v2) /\ mval_has_type ce (Tstruct M) v2
  /\ mem_next mm2 = mem_next mm1 /\ (forall b', b' <> b -> get_block mm2 b' = get_block mm1 b')
  /\ (forall a, In a L -> mval_get v2 (path_steps (fst (fst a))) = Some (MVscalar (Vint (snd a))))
  /\ (forall p', (forall a, In a L -> path_disjoint (path_steps (fst (fst a))) p') -> mval_get v2 p' = mval_get v1 p').
Proof.
  intros CS ctx w L; induction L as [|[[lp q] x] L IH]; intros le mm1 v1 Hle G1 H1 OK NDs.
  - exists mm1, v1. repeat split; auto. apply exec_Sskip. intros ? [].
  - destruct (OK _ (or_introl eq_refl)) as [R Tx]. simpl in R, Tx.
    destruct (eval_leaf m W ge [] le mm1 M lp q cmdE b [] R) as (A & T & _); auto.
    { apply eval_lvalue_deref_param; auto. }
    assert (Tp: type_at ce (Tstruct M) (path_steps lp) = Some (ctype_of_prim q)).
    { change (Tstruct M) with (ctype_of_ftype (FTmsg M)). rewrite type_at_ctype; auto.
      - rewrite R; reflexivity.
      - apply ftype_ok_msg. eapply resolve_leaf_msg; eauto. }
    assert (Hx: mval_has_type ce (ctype_of_prim q) (MVscalar (Vint x)))
      by (constructor; auto; apply ctype_of_prim_scalar_type).
    destruct (store_typed ce mm1 b (Tstruct M) v1 (path_steps lp) _ _ G1 H1 Tp Hx)
      as (mm2 & v2 & S & Sv & G2 & H2 & N2 & O2).
    simpl in NDs. inversion NDs as [|? ? Hnin ND']; subst.
    destruct (IH le mm2 v2) as (mm3 & v3 & X3 & G3 & H3 & N3 & O3 & Set3 & Keep3); auto.
    { intros a Ha; apply OK; simpl; auto. }
    exists mm3, v3. repeat split; auto.
    + simpl. change (@nil event) with (@nil event ++ @nil event).
      eapply exec_Sseq_1; [|exact X3].
      apply exec_Sassign. unfold const_store; simpl.
      rewrite app_nil_l in A.
      rewrite (eval_assign_scalar ge [] le mm1 _ _ b (path_steps lp) (Vint x) A).
      * rewrite T. unfold store. rewrite sem_cast_same by exact Tx. exact S.
      * rewrite T. apply ctype_of_prim_scalar_type.
      * exact (eval_const_of le mm1 q (Vint x) Tx).
    + congruence.
    + intros b' N. rewrite O3, O2; auto.
    + intros a [<-|Ha]; simpl.
      * rewrite Keep3; [eapply mval_get_set_same; eauto|].
        intros a' Ha'. destruct (OK a' (or_intror Ha')) as [R' _].
        apply (leaves_disjoint m _ _ (FTmsg M) _ q R' R).
        intros E. apply Hnin. rewrite <- E. apply (in_map (fun a => fst (fst a)) _ _ Ha').
      * apply Set3; auto.
    + intros p' D. rewrite Keep3 by (intros a Ha; apply D; simpl; auto).
      apply (mval_get_set_disjoint _ _ _ _ _ (D _ (or_introl eq_refl)) Sv).
Qed.

End OUTPUT.

(** The model without its constant strings. *)
Definition without_strings (m : node_model) : node_model :=
  {| nm_name := nm_name m; nm_period_ms := nm_period_ms m; nm_ctrl := nm_ctrl m;
     nm_in_var := nm_in_var m; nm_in_struct := nm_in_struct m; nm_inputs := nm_inputs m;
     nm_out_var := nm_out_var m; nm_out_struct := nm_out_struct m; nm_outputs := nm_outputs m;
     nm_msgs := nm_msgs m; nm_topics := nm_topics m; nm_inrels := nm_inrels m;
     nm_outrels := nm_outrels m; nm_timeouts := nm_timeouts m; nm_fallbacks := nm_fallbacks m;
     nm_drels := nm_drels m; nm_stamps := nm_stamps m; nm_stamp_from := nm_stamp_from m;
     nm_strings := [] |}.

(** What the output glue has written once the zeroing, the copies and
    the stamp have run: [DDC.published_value] of the model without its
    constant strings. *)
Definition pre_value (m : node_model) (y : mval) (now : Z) (g : ident -> mval) (tp : topic) (mv : mval) : Prop :=
  published_value (without_strings m) y now g tp mv.

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
    assert (Htop: In tp (nm_topics m)) by (apply in_published in Htp; tauto).
    assert (FT: find_topic (nm_topics m) (tp_cname tp) = Some tp)
      by (apply In_find_topic; [apply (wf_cnames_nodup m W)|auto]).
    assert (PRE: exists le2 mm2 v2,
        exec_stmt ctx ge [] le0 mm w (output_pre m tp) [] le2 mm2 w Out_normal
     /\ find_assoc command_param le2 = Some (Vptr b [])
     /\ get_block mm2 b = Some (Tstruct (tp_msg tp), v2)
     /\ unchanged_except mm mm2 b
     /\ pre_value m y (w_time w) (global_msg p mm) tp v2).
    { unfold pre_value, published_value. cbn [without_strings nm_outrels nm_stamps nm_stamp_from nm_strings].
      change (composites (without_strings m)) with (composites m).
      change (nm_msgs (without_strings m)) with (nm_msgs m). destruct (output_body tp Htp mm b by_ y NG Vy Gy Hy CS ctx w le0 mv0)
        as (le' & mm' & mv & X & Hle' & G' & [Tm [Rel Zero]] & [U1 U2]); auto.
      { unfold le0. apply find_assoc_set_same. }
      assert (Xb: exec_stmt ctx ge [] le0 mm w (output_base m tp) [] le' mm' w Out_normal).
      { unfold output_base, gen_list_message_expr_output_glue, gen_list_controller_expr_output_glue.
        rewrite copies_map. exact X. }
      assert (ROUT: forall o, In o (nm_outrels m) -> or_topic o = tp_cname tp ->
                    exists q, resolve msgs (FTmsg (tp_msg tp)) (or_path o) = Some (FTprim q)).
      { intros o Ho Eo. destruct (wf_outrel m o W Ho) as (tp' & t & q & Ft & _ & _ & _ & R).
        rewrite Eo, FT in Ft. inversion Ft; subst tp'. eauto. }
      destruct (topic_stamp m (tp_cname tp)) as [sp|] eqn:ST.
      + destruct (stamp_run tp Htp mm b GT NG CS ctx w le' mm' mv sp Hle' ST ltac:(intros b' Nb; destruct U1; auto) G' Tm)
          as (le2 & mm2 & v2 & X2 & Hle2 & G2 & H2 & N2 & O2 & STV & Keep).
        destruct (wf_stamp m tp sp W Htp ST) as (Rs & Rn & NO).
        assert (DJ: forall lp q, resolve msgs (FTmsg (tp_msg tp)) lp = Some (FTprim q) ->
                    lp <> sp ++ [PField "sec"%string] -> lp <> sp ++ [PField (stamp_nsec m)] ->
                    mval_get v2 (path_steps lp) = mval_get mv (path_steps lp)).
        { intros lp q R N1 N2'. apply Keep.
          - apply (leaves_disjoint m _ _ (FTmsg (tp_msg tp)) _ q Rs R). auto.
          - apply (leaves_disjoint m _ _ (FTmsg (tp_msg tp)) Puint32 q Rn R). auto. }
        exists le2, mm2, v2. split; [|split; [exact Hle2|split; [exact G2|split]]].
        * unfold output_pre. rewrite ST. change (@nil event) with (@nil event ++ @nil event). eapply exec_Sseq_1; eauto.
        * split; [congruence|]. intros b' Nb. rewrite O2, U2; auto.
        * split; [exact H2|split; [|split; [|split]]].
          -- intros o Ho Eo. destruct (Rel o Ho Eo) as (v & Yv & Mv). exists v. split; auto.
             destruct (ROUT o Ho Eo) as (q & R). rewrite DJ with (q := q); auto;
               intros E; apply (NO o _ Ho Eo E).
          -- intros sp' E. unfold topic_stamp in ST. rewrite ST in E. inversion E; subst sp'. exact STV.
          -- intros ? ? [].
          -- intros lp q R NOUT NS _. destruct (NS sp ST) as [N1 N2']. rewrite DJ with (q := q); auto.
      + exists le', mm', mv. split; [unfold output_pre; rewrite ST; exact Xb|split; [exact Hle'|split; [exact G'|split]]].
        * split; auto.
        * split; [exact Tm|split; [exact Rel|split; [|split]]].
          -- intros sp E. unfold topic_stamp in ST. rewrite ST in E. discriminate.
          -- intros ? ? [].
          -- intros lp q R NOUT _ _. apply Zero; auto. }
    destruct PRE as (le2 & mm2 & v2 & X2 & Hle2 & G2 & [U2n U2o] & (T2 & Rel2 & STV2 & _ & Zero2)).
    set (L := topic_stores m (tp_cname tp)).
    assert (OKs: forall a, In a L -> resolve msgs (FTmsg (tp_msg tp)) (fst (fst a)) = Some (FTprim (snd (fst a)))
                                  /\ val_has_type (Vint (snd a)) (ctype_of_prim (snd (fst a)))).
    { intros a Ha. apply In_topic_stores in Ha. destruct Ha as (sp & bs & Hs & Ha).
      apply (string_store_leaf m tp sp bs a W Htp Hs Ha). }
    destruct (exec_const_stores tp b CS ctx w L le2 mm2 v2 Hle2 G2 T2 OKs
                (topic_stores_nodup m _ W))
      as (mm3 & v3 & X3 & G3 & H3 & N3 & O3 & Set3 & Keep3).
    (* a leaf that no store writes keeps its value *)
    assert (KL: forall lp q, resolve msgs (FTmsg (tp_msg tp)) lp = Some (FTprim q) ->
                (forall a, In a L -> fst (fst a) <> lp) ->
                mval_get v3 (path_steps lp) = mval_get v2 (path_steps lp)).
    { intros lp q R N. apply Keep3. intros a Ha. destruct (OKs a Ha) as [Ra _].
      apply (leaves_disjoint m _ _ (FTmsg (tp_msg tp)) _ q Ra R). apply N; auto. }
    assert (NF: forall fl lp, fl <> "len"%string -> forall a, In a L -> fst (fst a) <> lp ++ [PField fl]).
    { intros fl lp Nf a Ha E. apply In_topic_stores in Ha. destruct Ha as (sp & bs & _ & Ha).
      destruct (string_stores_path _ _ _ Ha) as [[E1 _]|(i & b' & E1 & _)]; rewrite E1 in E.
      - apply app_inj_tail in E. destruct E as [_ E]. inversion E. auto.
      - replace [PField "data"%string; PIndex (Z.of_nat i)] with ([PField "data"%string] ++ [PIndex (Z.of_nat i)]) in E
          by reflexivity.
        rewrite app_assoc in E. apply app_inj_tail in E. destruct E as [_ E]. discriminate. }
    exists le2, mm3. split.
    + rewrite Fbody. change (@nil event) with (@nil event ++ @nil event). eapply exec_Sseq_1; eauto.
    + exists v3. split; [auto|split].
      * split; [exact H3|split; [|split; [|split]]].
        -- intros o Ho Eo. destruct (Rel2 o Ho Eo) as (v & Yv & Mv). exists v. split; auto.
           destruct (wf_outrel m o W Ho) as (tp' & t & q & Ft & _ & _ & _ & R).
           rewrite Eo, FT in Ft. inversion Ft; subst tp'.
           rewrite (KL _ q R); auto.
           intros a Ha E. apply In_topic_stores in Ha. destruct Ha as (sp & bs & Hs & Ha).
           destruct (wf_string m tp sp bs W Htp Hs) as (_ & _ & _ & _ & _ & _ & _ & NO).
           destruct (string_stores_path _ _ _ Ha) as [[E1 _]|(i & b' & E1 & _)]; rewrite E1 in E;
             symmetry in E; exact (NO o _ Ho Eo E).
        -- intros sp E. generalize (STV2 sp E).
           destruct (wf_stamp m tp sp W Htp E) as (Rs & Rn & _). fold (stamp_nsec m) in Rn.
           rewrite (KL _ _ Rs), (KL _ _ Rn)
             by (apply NF; unfold stamp_nsec, time_nsec_field; destruct (time_is_ros2 msgs); discriminate). auto.
        -- intros sp bs Hs. split.
           ++ apply (Set3 (_, Puint32, _)). apply In_topic_stores. exists sp, bs. split; auto.
              apply string_stores_len.
           ++ intros i b' Hb. apply (Set3 (_, Puint8, b')). apply In_topic_stores. exists sp, bs. split; auto.
              apply string_stores_data; auto.
        -- intros lp q R NOUT NS NSTR. rewrite (KL _ q R); [apply Zero2; auto; intros ? ? []|].
           intros a Ha E. apply In_topic_stores in Ha. destruct Ha as (sp & bs & Hs & Ha).
           destruct (NSTR sp bs Hs) as [N1 N2].
           destruct (string_stores_path _ _ _ Ha) as [[E1 _]|(i & b' & E1 & _ & _ & Hi)]; rewrite E1 in E.
           ++ apply N1; auto.
           ++ apply (N2 i Hi); auto.
      * split; [congruence|]. intros b' Nb. rewrite O3 by auto. auto.
Qed.

End GENERATED.
