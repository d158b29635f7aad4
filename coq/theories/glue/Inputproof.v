(** * T1 for the callbacks and the input glue *)

(** For every well-formed node model [m] and its program [p]
    ([generate m = OK p]), the generated callbacks meet [DDC.callback_ddc]
    (the paper's Figure 10) and [input_glue] meets [DDC.input_glue_ddc]
    (Figure 12): the copies of the input relations, the freshness of the
    timed topics (rule 4.12: fallbacks, derived inputs, the [c_new]
    flags) and the direct relations (rule 4.16).  The proofs run the
    bodies symbolically with [Copyproof.exec_copies].  The theorems are
    stated in [Glueproof]. *)

From Coq Require Import String List ZArith Bool Lia.
From ROSGen Require Import Errors Maps Syntax Values Operators Memory Environment Semantics NodeModel Wellformed Generator Generatorspec Generatorproof Assignproof.
From ROSGen Require Import DDC Copyproof.
From ROSGen Require Import Gluefacts.
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
Local Notation gen_leaf := (Gluefacts.gen_leaf m p GEN) (only parsing).
Local Notation gen_leaves_dp_nodup := (Gluefacts.gen_leaves_dp_nodup m p GEN) (only parsing).
Local Notation gen_leaves_disjoint := (Gluefacts.gen_leaves_disjoint m p GEN) (only parsing).
Local Notation gen_wf_composites := (Gluefacts.gen_wf_composites m p GEN) (only parsing).
Local Notation gen_zero_leaf := (Gluefacts.gen_zero_leaf m p GEN) (only parsing).
Local Notation gen_timed_is := (Gluefacts.gen_timed_is m) (only parsing).
Local Notation exec_assign_global := (Gluefacts.exec_assign_global p) (only parsing).
Local Notation exec_now_call := (Gluefacts.exec_now_call m p GEN) (only parsing).
Local Notation globals_typed_changed := (Gluefacts.globals_typed_changed m p GEN) (only parsing).
Local Notation gen_global_block := (Gluefacts.gen_global_block m p GEN) (only parsing).
Local Notation clock_run := (Gluefacts.clock_run m p GEN) (only parsing).

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

Lemma NoDup_map_filter_sub:
  forall (A B : Type) (f : A -> B) (P : A -> bool) l, NoDup (map f l) -> NoDup (map f (filter P l)).
Proof.
  intros A B f P l; induction l as [|a l IH]; simpl; intros Hnd; auto.
  inversion Hnd as [|? ? Hn Hnd']; subst. destruct (P a); simpl; auto.
  constructor; auto. intros Hin. apply Hn. apply in_map_iff in Hin. destruct Hin as (x & Ex & Hx).
  apply filter_In in Hx as [Hx _]. rewrite <- Ex. apply in_map; auto.
Qed.

Lemma In_read_leaves: forall l, In l (read_leaves m tp) -> In l (leaves msgs M).
Proof. intros l H. apply filter_In in H; tauto. Qed.

Lemma callback_body:
  forall (CS : Type) (ctx : ros_context CS) (w : world CS) le g0,
  le_ok le -> get_block mm bg = Some (Tstruct M, g0) -> mval_has_type ce (Tstruct M) g0 ->
  exists le' mm' g,
     exec_stmt ctx ge [] le mm w
       (seq_of (map (leaf_copy ce dstE srcE) (read_leaves m tp))) [] le' mm' w Out_normal
  /\ get_block mm' bg = Some (Tstruct M, g)
  /\ mval_has_type ce (Tstruct M) g
  /\ reads_copied m tp mv g0 g
  /\ unchanged_except mm mm' bg
  /\ find_assoc msg_param le' = Some (Vptr b []).
Proof.
  intros CS ctx w le g0 Hle Gg Hg0.
  destruct (exec_copies ctx ge [] w ce _ snd (fun l => path_expr ce dstE (fst l))
              (fun l => path_expr ce srcE (fst l)) (fun l => path_steps (fst l)) sv
              le_ok callback_le_ok_set mm bg (Tstruct M) (read_leaves m tp) le mm g0)
    as (le' & mm' & v' & X & Hle' & Fr & G' & Hv' & Set' & Keep'); auto.
  - split; auto.
  - intros l Hl. apply callback_item_ok, In_read_leaves; auto.
  - apply NoDup_map_filter_sub, gen_leaves_dp_nodup.
  - intros a1 a2 H1 H2. apply (gen_leaves_disjoint M); apply In_read_leaves; auto.
  - exists le', mm', v'. split; [exact X|]. split; [exact G'|]. split; [exact Hv'|].
    split; [|split; [apply frame_unchanged; auto|exact Hle']].
    intros lp q R. assert (Hl: In (lp, q) (leaves msgs M)) by (apply leaves_spec; auto).
    destruct (is_read m c lp) eqn:Rd.
    + assert (Hr: In (lp, q) (read_leaves m tp)) by (apply filter_In; auto).
      generalize (Set' (lp, q) Hr); cbn [fst]; intros ->.
      destruct (leaf_typed m W M lp q mv R Hmv) as (x & Gx & _).
      rewrite Gx. unfold sv. simpl. rewrite (scalar_at_spec _ _ _ Gx). auto.
    + apply Keep'. intros a Ha. apply (gen_leaves_disjoint M a (lp, q)); auto.
      * apply In_read_leaves; auto.
      * cbn [fst]. intros E. apply path_steps_inj in E.
        apply filter_In in Ha as [_ Ra]. rewrite E, Rd in Ra. discriminate.
Qed.

End CALLBACK.

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

(** Two distinct leaves of a controller field are disjoint: both are the
    field itself, or two different elements. *)
Lemma ctrl_leaves_disjoint:
  forall t p1 p2 q1 q2, ctrl_ftype_ok t = true -> ctrl_prim t p1 = Some q1 -> ctrl_prim t p2 = Some q2 ->
  p1 <> p2 -> path_disjoint (path_steps p1) (path_steps p2).
Proof.
  intros t p1 p2 q1 q2 OK R1 R2 N.
  destruct (ctrl_leaf_cases t p1 q1 OK R1) as [[E1 ->]|(n1 & i1 & E1 & -> & B1)];
  destruct (ctrl_leaf_cases t p2 q2 OK R2) as [[E2 ->]|(n2 & i2 & E2 & -> & B2)];
    subst t; try discriminate; [congruence|].
  simpl. left. intros E. inversion E. congruence.
Qed.

(** A leaf [v.x.p] of a controller field of type [t] in a global [v]:
    the place of the field's leaf, of its primitive's type, read by a
    scalar load. *)
Lemma eval_ctrl_leaf:
  forall ge e le mm v x t pa q id bv,
  ctrl_ftype_ok t = true -> ctrl_prim t pa = Some q ->
  Generator.field_type ce id x = Some (ctype_of_ftype t) ->
  eval_lvalue ge e le mm (Evar v (Tstruct id)) = Some (bv, []) ->
     eval_lvalue ge e le mm (path_expr ce (Evar v (Tstruct id)) (PField x :: pa)) = Some (bv, Sfield x :: path_steps pa)
  /\ typeof (path_expr ce (Evar v (Tstruct id)) (PField x :: pa)) = ctype_of_prim q
  /\ eval_expr ge e le mm (path_expr ce (Evar v (Tstruct id)) (PField x :: pa))
     = load (ctype_of_prim q) mm bv (Sfield x :: path_steps pa).
Proof.
  intros ge e le mm v x t pa q id bv OK Q FT E.
  destruct (ctrl_leaf_resolve msgs (md_names msgs) t pa q OK Q) as [Ft Rt].
  assert (E1: eval_lvalue ge e le mm (Efield (Evar v (Tstruct id)) x (ctype_of_ftype t)) = Some (bv, [Sfield x])).
  { change [Sfield x] with ([] ++ [Sfield x]). eapply eval_lvalue_field; [reflexivity|exact E]. }
  assert (EQ: path_expr ce (Evar v (Tstruct id)) (PField x :: pa)
              = path_expr ce (Efield (Evar v (Tstruct id)) x (ctype_of_ftype t)) pa).
  { cbn [path_expr step_expr]. unfold step_type. cbn [typeof]. rewrite FT. reflexivity. }
  destruct (eval_lvalue_path m W ge e le mm pa t (FTprim q) (Efield (Evar v (Tstruct id)) x (ctype_of_ftype t))
              bv [Sfield x] Ft Rt eq_refl E1) as [A B].
  rewrite <- EQ in A, B. split; [exact A|]. split; [exact B|].
  destruct (path_expr_lvalue_form m (PField x :: pa) (Evar v (Tstruct id)) ltac:(discriminate))
    as [(a & f & ty & Ea)|(a & i & ty & Ea)]; rewrite Ea in *.
  - rewrite (eval_expr_lvalue ge e le mm (Efield a f ty) I). simpl in B. subst ty.
    simpl typeof. rewrite A. reflexivity.
  - rewrite (eval_expr_lvalue ge e le mm (Eindex a i ty) I). simpl in B. subst ty.
    simpl typeof. rewrite A. reflexivity.
Qed.

(** The destinations of two input relations are the same leaf of the
    controller's inputs or disjoint ones. *)
Lemma input_leaves_disjoint:
  forall ir1 ir2, In ir1 (nm_inrels m) -> In ir2 (nm_inrels m) ->
  Sfield (ir_input ir1) :: path_steps (ir_elem ir1) <> Sfield (ir_input ir2) :: path_steps (ir_elem ir2) ->
  path_disjoint (Sfield (ir_input ir1) :: path_steps (ir_elem ir1)) (Sfield (ir_input ir2) :: path_steps (ir_elem ir2)).
Proof.
  intros ir1 ir2 H1 H2 N. simpl.
  destruct (string_dec (ir_input ir1) (ir_input ir2)) as [E|E]; [right|left; congruence].
  destruct (wf_inrel m ir1 W H1) as (_ & t1 & q1 & _ & _ & I1 & Q1 & _).
  destruct (wf_inrel m ir2 W H2) as (_ & t2 & q2 & _ & _ & I2 & Q2 & _).
  rewrite E, I2 in I1. inversion I1; subst t2.
  apply (ctrl_leaves_disjoint t1 _ _ q1 q2); auto.
  - apply (wf_inputs_ok m W (ir_input ir1, t1)). apply find_assoc_In. rewrite E; auto.
  - intros Ep. apply N. rewrite E, Ep. auto.
Qed.

Lemma NoDup_map_eq:
  forall (A B : Type) (f : A -> B) l a b, NoDup (map f l) -> In a l -> In b l -> f a = f b -> a = b.
Proof.
  induction l as [|x l IH]; simpl; intros a b N Ha Hb E; [contradiction|].
  inversion N as [|? ? Hn N']; subst.
  destruct Ha as [<-|Ha], Hb as [<-|Hb]; auto.
  - elim Hn. rewrite E. apply in_map; auto.
  - elim Hn. rewrite <- E. apply in_map; auto.
Qed.

Lemma input_leaves_nodup: NoDup (map input_leaf (nm_inrels m)).
Proof.
  unfold input_leaf.
  rewrite <- (map_map (fun ir => (ir_input ir, ir_elem ir)) (fun xp => Sfield (fst xp) :: path_steps (snd xp))).
  apply NoDup_map_inj.
  - intros [x1 p1] [x2 p2] E; inversion E as [[E1 E2]]. apply path_steps_inj in E2. subst; auto.
  - apply wf_inrel_inputs_nodup; auto.
Qed.

(** The leaves of two different input relations are disjoint. *)
Lemma input_leaves_distinct:
  forall ir1 ir2, In ir1 (nm_inrels m) -> In ir2 (nm_inrels m) -> ir1 <> ir2 ->
  path_disjoint (input_leaf ir1) (input_leaf ir2).
Proof.
  intros ir1 ir2 H1 H2 N. apply input_leaves_disjoint; auto.
  intros E. apply N. apply (NoDup_map_eq _ _ input_leaf (nm_inrels m)); auto. apply input_leaves_nodup.
Qed.

(** The leaf of an input relation in [Controller_U] has the C type of
    the relation's primitive, and holds a scalar in any value of the
    inputs' type. *)
Lemma gen_input_leaf_type:
  forall ir, In ir (nm_inrels m) ->
  type_at ce (Tstruct (nm_in_struct m)) (input_leaf ir) = Some (ctype_of_prim (inrel_prim (make_tables m) ir)).
Proof.
  intros ir Hir.
  destruct (input_exprs m ir W Hir) as (tp' & t & q & _ & _ & _ & I & Q & _ & Pq & _ & _).
  assert (OKt: ctrl_ftype_ok t = true) by (apply (wf_inputs_ok m W (ir_input ir, t)); apply find_assoc_In; auto).
  destruct (ctrl_leaf_resolve msgs (md_names msgs) t (ir_elem ir) q OKt Q) as [Ft Rt].
  assert (FT := field_type_inputs m W _ _ I).
  rewrite Pq. unfold input_leaf. cbn [type_at]. rewrite type_step_field, FT.
  rewrite (type_at_ctype m W); auto. rewrite Rt; auto.
Qed.

Lemma gen_input_leaf_scalar:
  forall ir u, In ir (nm_inrels m) -> mval_has_type ce (Tstruct (nm_in_struct m)) u ->
  exists v, mval_get u (input_leaf ir) = Some (MVscalar v).
Proof.
  intros ir u Hir Hu.
  destruct (mval_get_has_type _ _ _ _ _ Hu (gen_input_leaf_type ir Hir)) as [x [G Hx]].
  inversion Hx; subst; eauto; destruct (inrel_prim (make_tables m) ir); discriminate.
Qed.

(** The destination of the copy of an input relation: the relation's
    leaf of [Controller_U], of the relation's primitive's C type. *)
Lemma input_dst_place:
  forall bu, find_var ge (nm_in_var m) = Some (bu, Tstruct (nm_in_struct m)) ->
  forall ir, In ir (nm_inrels m) ->
     (forall le mm1, eval_lvalue ge [] le mm1 (input_dst m ir) = Some (bu, input_leaf ir))
  /\ typeof (input_dst m ir) = ctype_of_prim (inrel_prim (make_tables m) ir)
  /\ type_at ce (Tstruct (nm_in_struct m)) (input_leaf ir) = Some (ctype_of_prim (inrel_prim (make_tables m) ir)).
Proof.
  intros bu Vu ir Hir.
  destruct (input_exprs m ir W Hir) as (tp' & t & q & _ & _ & _ & I & Q & _ & Pq & _ & _).
  assert (OKt: ctrl_ftype_ok t = true) by (apply (wf_inputs_ok m W (ir_input ir, t)); apply find_assoc_In; auto).
  destruct (ctrl_leaf_resolve msgs (md_names msgs) t (ir_elem ir) q OKt Q) as [Ft Rt].
  assert (FT := field_type_inputs m W _ _ I).
  split; [|split; [|apply gen_input_leaf_type; auto]]; rewrite ?Pq.
  - intros le mm1. unfold input_dst, in_var_expr, input_leaf. cbn [path_expr step_expr]. unfold step_type.
    cbn [typeof]. rewrite FT.
    change (Sfield (ir_input ir) :: path_steps (ir_elem ir)) with ([Sfield (ir_input ir)] ++ path_steps (ir_elem ir)).
    eapply (eval_lvalue_path m W); eauto.
    change [Sfield (ir_input ir)] with ([] ++ [Sfield (ir_input ir)]).
    eapply eval_lvalue_field; [reflexivity|]. eapply eval_lvalue_global_struct; eauto.
  - unfold input_dst. rewrite typeof_path_expr with (t := ctype_of_prim q); auto.
    apply (input_leaf_type m W _ _ _ _ I Q).
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
  exists tp t q bg g x,
     tp_cname tp = ir_topic ir /\ In tp (subscribed m)
  /\ find_assoc (ir_input ir) (nm_inputs m) = Some t
  /\ ctrl_prim t (ir_elem ir) = Some q
  /\ resolve msgs (FTmsg (tp_msg tp)) (ir_path ir) = Some (FTprim q)
  /\ inrel_prim (make_tables m) ir = q
  /\ input_src m (make_tables m) ir = path_expr ce (Evar (msg_var (ir_topic ir)) (Tstruct (tp_msg tp))) (ir_path ir)
  /\ input_dst m ir = path_expr ce (Evar (nm_in_var m) (Tstruct (nm_in_struct m))) (PField (ir_input ir) :: ir_elem ir)
  /\ find_var ge (msg_var (ir_topic ir)) = Some (bg, Tstruct (tp_msg tp))
  /\ get_block mm bg = Some (Tstruct (tp_msg tp), g)
  /\ bg <> bu
  /\ global_value p mm (msg_var (ir_topic ir)) = Some g
  /\ mval_get g (path_steps (ir_path ir)) = Some (MVscalar x)
  /\ val_has_type x (ctype_of_prim q)
  /\ sv ir = x.
Proof.
  intros ir Hir.
  destruct (input_exprs m ir W Hir) as (tp & t & q & _ & Ec & Hs & I & Q & R & Pq & Es & Ed).
  destruct (generate_callback m p tp GEN Hs) as [Fv _].
  destruct (gen_var _ _ Fv) as [bg Vg]. rewrite Ec in Vg.
  destruct (GT _ _ _ Vg) as (g & Gg & Hg). rewrite gen_types in Hg.
  destruct (leaf_typed m W _ _ _ g R Hg) as (x & Gx & Tx).
  assert (GV: global_value p mm (msg_var (ir_topic ir)) = Some g)
    by (unfold global_value; rewrite Vg, Gg; auto).
  exists tp, t, q, bg, g, x. repeat split; auto.
  - eapply globalenv_vars_disjoint; eauto. rewrite <- Ec. apply gen_in_out_vars; auto.
  - unfold sv, gval. rewrite GV. apply scalar_at_spec; auto.
Qed.

Lemma input_item_ok:
  forall ir, In ir (nm_inrels m) ->
  item_ok ge [] ce _ (fun ir => inrel_prim (make_tables m) ir) (input_dst m) (input_src m (make_tables m))
          input_leaf sv (fun _ => True) mm bu (Tstruct (nm_in_struct m)) ir.
Proof.
  intros ir Hir.
  destruct (input_source ir Hir) as (tp & t & q & bg & g & x & Ec & Hs & I & Q & R & Pq & Es & Ed & Vg & Gg & Nbg & GV & Gx & Tx & Sx).
  destruct (input_dst_place bu Vu ir Hir) as (D1 & D2 & D3).
  unfold item_ok. rewrite Pq in *. rewrite Sx. repeat split; auto.
  intros le mm1 _ [Fn Fo]. rewrite Es.
  destruct (eval_leaf m W ge [] le mm1 (tp_msg tp) (ir_path ir) q
              (Evar (msg_var (ir_topic ir)) (Tstruct (tp_msg tp))) bg [] R) as (_ & _ & E); auto.
  { eapply eval_lvalue_global_struct; eauto. }
  rewrite E. apply load_spec; [apply ctype_of_prim_scalar_type|].
  unfold load_path. rewrite Fo by auto. rewrite Gg. auto.
Qed.

Lemma input_body:
  forall (CS : Type) (ctx : ros_context CS) (w : world CS) le u0,
  get_block mm bu = Some (Tstruct (nm_in_struct m), u0) ->
  mval_has_type ce (Tstruct (nm_in_struct m)) u0 ->
  exists le' mm' u,
     exec_stmt ctx ge [] le mm w
       (seq_of (map (fun ir => copy (inrel_prim (make_tables m) ir) (input_dst m ir) (input_src m (make_tables m) ir))
                    (glue_inrels m))) [] le' mm' w Out_normal
  /\ get_block mm' bu = Some (Tstruct (nm_in_struct m), u)
  /\ unchanged_except mm mm' bu
  /\ mval_has_type ce (Tstruct (nm_in_struct m)) u
  /\ (forall ir, In ir (glue_inrels m) ->
       exists g v, global_value p mm (msg_var (ir_topic ir)) = Some g
         /\ mval_get g (path_steps (ir_path ir)) = Some (MVscalar v)
         /\ mval_get u (Sfield (ir_input ir) :: path_steps (ir_elem ir)) = Some (MVscalar v))
  /\ (forall ir, In ir (nm_inrels m) -> is_direct m ir = true ->
       mval_get u (input_leaf ir) = mval_get u0 (input_leaf ir)).
Proof.
  intros CS ctx w le u0 Gu Hu0.
  destruct (exec_copies ctx ge [] w ce _ (fun ir => inrel_prim (make_tables m) ir) (input_dst m) (input_src m (make_tables m))
              input_leaf sv (fun _ => True) (fun _ _ _ _ => I)
              mm bu (Tstruct (nm_in_struct m)) (glue_inrels m) le mm u0)
    as (le' & mm' & u & X & _ & Fr & G' & Hu & Set' & Keep'); auto.
  - split; auto.
  - intros ir Hir. apply input_item_ok, incl_glue_inrels; auto.
  - apply NoDup_map_filter_sub, input_leaves_nodup.
  - intros a1 a2 H1 H2 N. apply input_leaves_disjoint; auto; apply incl_glue_inrels; auto.
  - exists le', mm', u. split; [exact X|]. split; [exact G'|]. split; [apply frame_unchanged; auto|].
    split; [exact Hu|]. split.
    + intros ir Hir.
      destruct (input_source ir (incl_glue_inrels m ir Hir))
        as (tp & t & q & bg & g & x & _ & _ & _ & _ & _ & _ & _ & _ & _ & _ & _ & GV & Gx & _ & Sx).
      exists g, x. repeat split; auto. unfold input_leaf in Set'. rewrite Set'; auto. rewrite Sx; auto.
    + intros ir Hir D. apply Keep'. intros a Ha. assert (Ha' := Ha). apply glue_inrels_In in Ha' as [Ha' Da].
      apply input_leaves_distinct; auto. intros ->. congruence.
Qed.

End INPUT.

(** *** Freshness (rule 4.12) *)



Lemma clock_range: forall t, (0 <= clock t <= max_ulong)%Z.
Proof.
  intros t. unfold clock, norm_long, wrap, wrap_unsigned, max_ulong.
  generalize (Z.mod_pos_bound t (2 ^ 64) ltac:(reflexivity)). change (2 ^ 64)%Z with 18446744073709551616%Z. lia.
Qed.

Lemma age_ns_range: forall rcv now, (0 <= age_ns rcv now <= max_ulong)%Z.
Proof.
  intros [t|] now; simpl; [|rewrite ulong_max_agrees; unfold max_ulong; lia].
  generalize (clock_range t) (clock_range now). intros.
  destruct (Z.leb_spec (clock t) (clock now)); lia.
Qed.

Lemma in_range_ulong: forall n, (0 <= n <= max_ulong)%Z -> in_range 64 Unsigned n = true.
Proof.
  intros n H. unfold in_range, int_min, int_max, max_ulong in *. apply andb_true_iff.
  split; apply Z.leb_le; change (2 ^ 64 - 1)%Z with 18446744073709551615%Z; lia.
Qed.

Lemma wrap_ulong: forall n, (0 <= n <= max_ulong)%Z -> wrap_unsigned 64 n = n.
Proof.
  intros n H. unfold wrap_unsigned, max_ulong in *. apply Z.mod_small.
  change (2 ^ 64)%Z with 18446744073709551616%Z. lia.
Qed.

(** [age_ms]: the milliseconds, saturated. *)
Lemma age_ms_sat:
  forall a, (0 <= a)%Z ->
  (if (a <=? max_age_ns)%Z then (a / 1000000)%Z else max_uint) = Z.min (a / 1000000) max_uint.
Proof.
  intros a Ha. unfold max_age_ns, max_uint. destruct (Z.leb_spec a 4294967295999999) as [L|L].
  - assert (a / 1000000 < 4294967296)%Z by (apply Z.div_lt_upper_bound; lia).
    rewrite Z.min_l; lia.
  - assert (4294967295 <= a / 1000000)%Z by (apply Z.div_le_lower_bound; lia).
    rewrite Z.min_r; lia.
Qed.

Lemma in_timed: forall tp, In tp (subscribed m) -> is_timed m (tp_cname tp) = true -> In tp (timed m).
Proof. intros tp H T. apply filter_In; auto. Qed.

(** The subscribed topic of a C name, if any. *)
Lemma timed_of_cname:
  forall c, is_timed m c = true -> (exists tp, In tp (subscribed m) /\ tp_cname tp = c) ->
  exists tp, In tp (timed m) /\ tp_cname tp = c.
Proof. intros c T (tp & H & <-). exists tp; split; auto. apply in_timed; auto. Qed.

(** An input relation into a scalar input feeds the input itself. *)
Lemma scalar_input_elem:
  forall ir q, In ir (nm_inrels m) -> find_assoc (ir_input ir) (nm_inputs m) = Some (FTprim q) -> ir_elem ir = [].
Proof.
  intros ir q H F. destruct (wf_inrel m ir W H) as (_ & t & q' & _ & _ & I & Q & _).
  rewrite F in I; inversion I; subst t. destruct (ir_elem ir) as [|[f|i] pa]; auto; discriminate.
Qed.

Lemma input_dst_scalar:
  forall ir q, In ir (nm_inrels m) -> find_assoc (ir_input ir) (nm_inputs m) = Some (FTprim q) ->
  input_dst m ir = Efield (in_var_expr m) (ir_input ir) (ctype_of_prim q).
Proof.
  intros ir q H F. unfold input_dst. rewrite (scalar_input_elem ir q H F). cbn [path_expr step_expr].
  unfold step_type, in_var_expr. cbn [typeof]. rewrite (field_type_inputs m W _ _ F). reflexivity.
Qed.

Lemma fallback_topic:
  forall ir fv, In ir (nm_inrels m) -> find_assoc (ir_input ir) (nm_fallbacks m) = Some fv ->
  exists tp t, In tp (timed m) /\ tp_cname tp = ir_topic ir /\ timeout_of m (ir_topic ir) = Some t
            /\ val_has_type fv (ctype_of_prim (inrel_prim (make_tables m) ir))
            /\ (0 < t * 1000000 < max_ulong)%Z.
Proof.
  intros ir fv Hir F.
  destruct (wf_fallback m (ir_input ir) fv W (find_assoc_In _ _ _ _ F)) as (q & ir' & t & Q & Tv & Hir' & E & Ht).
  assert (ir' = ir).
  { apply (NoDup_map_eq _ _ (fun ir => (ir_input ir, ir_elem ir)) (nm_inrels m)); auto.
    - apply wf_inrel_inputs_nodup; auto.
    - rewrite (scalar_input_elem ir' q), (scalar_input_elem ir q), E; auto. rewrite E; auto. }
  subst ir'.
  destruct (wf_timeout m _ _ W Ht) as (tp & Ft & S & Rt).
  apply find_topic_In in Ft. destruct Ft as [Ft Ec].
  assert (Hs: In tp (subscribed m)) by (apply in_subscribed; split; auto; unfold is_subscribed in S; destruct (tp_dir tp); [auto|discriminate]).
  destruct (timeout_of m (ir_topic ir)) as [t'|] eqn:TO.
  2:{ exfalso. unfold timeout_of in TO. apply find_assoc_None in TO. apply TO. apply in_map_iff. exists (ir_topic ir, t); auto. }
  assert (Ht': In (ir_topic ir, t') (nm_timeouts m)) by (apply find_assoc_In; auto).
  assert (t' = t).
  { assert (E2: (ir_topic ir, t') = (ir_topic ir, t)).
    { apply (NoDup_map_eq _ _ fst (nm_timeouts m)); auto. apply wf_timeouts_nodup; auto. }
    congruence. }
  subst t'.
  exists tp, t. repeat split; auto.
  - apply in_timed; auto. rewrite Ec. unfold is_timed. apply orb_true_iff; left.
    apply existsb_exists. exists (ir_topic ir, t); split; auto. apply ident_eqb_refl.
  - unfold inrel_prim. rewrite (input_prim_tables m _ _ (ir_elem ir) q Q); auto.
    rewrite (scalar_input_elem ir q); auto.
  - unfold max_timeout_ms in Rt. generalize (wf_period m W). lia.
  - unfold max_timeout_ms, max_ulong in *. lia.
Qed.

Lemma drel_topic:
  forall dr, In dr (nm_drels m) ->
  exists tp, In tp (timed m) /\ tp_cname tp = dr_topic dr
          /\ input_prim (make_tables m) (dr_input dr) [] = derived_prim (dr_kind dr).
Proof.
  intros dr Hdr. destruct (wf_drel m dr W Hdr) as (tp & Ft & S & I).
  apply find_topic_In in Ft. destruct Ft as [Ft Ec].
  exists tp. repeat split; auto.
  - apply in_timed.
    + apply in_subscribed; split; auto. unfold is_subscribed in S; destruct (tp_dir tp); [auto|discriminate].
    + rewrite Ec. unfold is_timed. apply orb_true_iff; right.
      apply existsb_exists. exists dr; split; auto. apply ident_eqb_refl.
  - eapply input_prim_tables; eauto; reflexivity.
Qed.

Section FRESH.

Context {CS : Type}.
Variables (ctx : ros_context CS) (w : world CS).
Variables (mm1 : mem) (bu : block) (ck : ident -> bool * option Z).
Hypothesis Vu : find_var ge (nm_in_var m) = Some (bu, Tstruct (nm_in_struct m)).
Hypothesis CK : forall tp, In tp (timed m) ->
  clock_held p mm1 (tp_cname tp) (fst (ck (tp_cname tp))) (snd (ck (tp_cname tp))).

Local Notation now := (w_time w).
Local Notation UT := (Tstruct (nm_in_struct m)).
Let le_ok (le : temp_env) : Prop := reads_age m = true -> find_assoc now_temp le = Some (Vlong (clock now)).
Let fr (mm : mem) : Prop := frame mm1 bu mm.

Lemma le_ok_set: forall le x v, x <> now_temp -> le_ok le -> le_ok (set_assoc x v le).
Proof. intros le x v N H R. rewrite find_assoc_set_other; auto. Qed.

Lemma eval_clock_global:
  forall tp x ty v le mm, In tp (timed m) -> In x (clock_names tp) -> find_def p x = Some (Gvar ty) ->
  is_scalar_type ty = true -> fr mm -> global_value p mm1 x = Some (MVscalar v) ->
  eval_expr ge [] le mm (Evar x ty) = Some v.
Proof.
  intros tp x ty v le mm Ht Hx F S [Fn Fo] GV.
  destruct (gen_var _ _ F) as [bx V].
  assert (Nx: x <> nm_in_var m).
  { intros ->. destruct (wf_controller_vars_fresh m W) as (_ & NU & _). apply NU.
    eapply clock_name_in_after; eauto. }
  assert (Nb: bx <> bu) by (eapply globalenv_vars_disjoint; eauto).
  unfold global_value in GV. rewrite V in GV.
  destruct (get_block mm1 bx) as [[t0 mv]|] eqn:G; inversion GV; subst mv.
  assert (L: load ty mm bx [] = Some v).
  { apply load_spec; auto. unfold load_path. rewrite Fo by auto. rewrite G. reflexivity. }
  destruct ty; try discriminate; cbn [eval_expr]; unfold load_loc, lvalue_var; cbn [find_assoc]; rewrite V; exact L.
Qed.

Lemma eval_new:
  forall tp le mm, In tp (timed m) -> fr mm ->
  eval_expr ge [] le mm (new_expr (tp_cname tp)) = Some (Vint (if fst (ck (tp_cname tp)) then 1 else 0)).
Proof.
  intros tp le mm Ht Fr. destruct (generate_clock_globals m p tp GEN Ht) as (_ & Fn & _).
  destruct (CK tp Ht) as (Cn & _ & _).
  apply (eval_clock_global tp _ _ _ le mm Ht (or_intror (or_introl eq_refl)) Fn eq_refl Fr Cn).
Qed.

Lemma eval_rcvd:
  forall tp le mm, In tp (timed m) -> fr mm ->
  eval_expr ge [] le mm (rcvd_expr (tp_cname tp))
  = Some (Vint (match snd (ck (tp_cname tp)) with Some _ => 1 | None => 0 end)).
Proof.
  intros tp le mm Ht Fr. destruct (generate_clock_globals m p tp GEN Ht) as (_ & _ & Fr').
  destruct (CK tp Ht) as (_ & Cr & _).
  apply (eval_clock_global tp _ _ _ le mm Ht (or_intror (or_intror (or_introl eq_refl))) Fr' eq_refl Fr Cr).
Qed.

Lemma eval_time:
  forall tp t le mm, In tp (timed m) -> fr mm -> snd (ck (tp_cname tp)) = Some t ->
  eval_expr ge [] le mm (time_expr (tp_cname tp)) = Some (Vlong (clock t)).
Proof.
  intros tp t le mm Ht Fr E. destruct (generate_clock_globals m p tp GEN Ht) as (Ft & _ & _).
  destruct (CK tp Ht) as (_ & _ & Ct).
  apply (eval_clock_global tp _ _ _ le mm Ht (or_introl eq_refl) Ft eq_refl Fr (Ct t E)).
Qed.

(** The age of the newest message of a timed topic. *)
Lemma age_run:
  forall tp le mm, In tp (timed m) -> find_assoc now_temp le = Some (Vlong (clock now)) -> fr mm ->
  exec_stmt ctx ge [] le mm w (age_stmt (tp_cname tp)) []
            (set_assoc age_temp (Vlong (age_ns (snd (ck (tp_cname tp))) now)) le) mm w Out_normal.
Proof.
  intros tp le mm Ht Hle Fr. unfold age_stmt.
  destruct (snd (ck (tp_cname tp))) as [t|] eqn:E.
  - eapply exec_Sifthenelse; [apply eval_rcvd; eauto|rewrite E; reflexivity|].
    simpl.
    generalize (clock_range t) (clock_range now). intros Rt Rn.
    eapply exec_Sifthenelse.
    + cbn [eval_expr typeof]. simpl binop_type. rewrite (eval_time tp t le mm Ht Fr E). simpl.
      rewrite Hle. simpl.
      unfold int_binop. rewrite (in_range_ulong _ Rt), (in_range_ulong _ Rn). reflexivity.
    + reflexivity.
    + unfold age_ns. simpl negb.
      destruct (Z.leb (clock t) (clock now)) eqn:L; simpl.
      * apply exec_Sset. cbn [eval_expr typeof]. simpl binop_type. rewrite (eval_time tp t le mm Ht Fr E).
        simpl. rewrite Hle. simpl.
        unfold int_binop. rewrite (in_range_ulong _ Rt), (in_range_ulong _ Rn). simpl.
        rewrite wrap_ulong; auto. apply Z.leb_le in L. lia.
      * apply exec_Sset. reflexivity.
  - eapply exec_Sifthenelse; [apply eval_rcvd; eauto|rewrite E; reflexivity|].
    simpl. apply exec_Sset. reflexivity.
Qed.

(** A store into the field [x] of [Controller_U]. *)
Lemma exec_store_input:
  forall le mm u x q rhs v,
  find_assoc x (nm_inputs m) = Some (FTprim q) -> get_block mm bu = Some (UT, u) -> mval_has_type ce UT u ->
  eval_expr ge [] le mm rhs = Some v -> val_has_type v (ctype_of_prim q) ->
  exists mm' u',
     exec_stmt ctx ge [] le mm w (Sassign (Efield (in_var_expr m) x (ctype_of_prim q)) rhs) [] le mm' w Out_normal
  /\ get_block mm' bu = Some (UT, u') /\ mval_has_type ce UT u'
  /\ mval_set u [Sfield x] (MVscalar v) = Some u'
  /\ mem_next mm' = mem_next mm /\ (forall b', b' <> bu -> get_block mm' b' = get_block mm b').
Proof.
  intros le mm u x q rhs v I G Hu E T.
  assert (Tp: type_at ce UT [Sfield x] = Some (ctype_of_prim q)).
  { cbn [type_at]. rewrite type_step_field, (field_type_inputs m W _ _ I). auto. }
  assert (Hx: mval_has_type ce (ctype_of_prim q) (MVscalar v)) by (constructor; auto; apply ctype_of_prim_scalar_type).
  destruct (store_typed ce mm bu UT u [Sfield x] _ _ G Hu Tp Hx) as (mm' & u' & S & Sv & G' & Hu' & N' & O').
  exists mm', u'. repeat split; auto.
  apply exec_Sassign.
  rewrite (eval_assign_scalar ge [] le mm _ _ bu [Sfield x] v).
  - simpl typeof. unfold store. rewrite sem_cast_same by exact T. exact S.
  - change [Sfield x] with ([] ++ [Sfield x]). eapply eval_lvalue_field; [reflexivity|].
    unfold in_var_expr. eapply eval_lvalue_global_struct; eauto.
  - apply ctype_of_prim_scalar_type.
  - exact E.
Qed.

Lemma eval_const_of:
  forall le mm q v, val_has_type v (ctype_of_prim q) -> eval_expr ge [] le mm (const_of q v) = Some v.
Proof.
  intros le mm q v T. unfold const_of.
  destruct v, q; simpl in T; try contradiction; cbn [eval_expr ctype_of_prim];
    first [reflexivity | f_equal; f_equal; exact T].
Qed.

(** The items of the freshness: a fallback or a derived input, the
    input field it writes, and what it writes there ([None]: nothing). *)
Definition item_stmt (a : inrel + drel) : statement :=
  match a with inl ir => fallback_stmt m (make_tables m) ir | inr dr => derived_stmt m (make_tables m) dr end.

Definition item_field (a : inrel + drel) : ident :=
  match a with inl ir => ir_input ir | inr dr => dr_input dr end.

Definition item_val (a : inrel + drel) : option val :=
  match a with
  | inl ir =>
      match find_assoc (ir_input ir) (nm_fallbacks m) with
      | Some fv => if stale m (ir_topic ir) (snd (ck (ir_topic ir))) now then Some fv else None
      | None => None
      end
  | inr dr => Some (derived_value (dr_kind dr) (fst (ck (dr_topic dr))) (snd (ck (dr_topic dr))) now)
  end.

Definition item_run (a : inrel + drel) : Prop :=
  forall le mm u, le_ok le -> fr mm -> get_block mm bu = Some (UT, u) -> mval_has_type ce UT u ->
  exists le' mm' u',
     exec_stmt ctx ge [] le mm w (item_stmt a) [] le' mm' w Out_normal
  /\ le_ok le' /\ fr mm' /\ get_block mm' bu = Some (UT, u') /\ mval_has_type ce UT u'
  /\ mval_get u' [Sfield (item_field a)]
     = match item_val a with Some v => Some (MVscalar v) | None => mval_get u [Sfield (item_field a)] end
  /\ (forall y, y <> item_field a -> mval_get u' [Sfield y] = mval_get u [Sfield y]).

Lemma now_age: now_temp <> age_temp.
Proof. discriminate. Qed.

Lemma stale_age:
  forall c t rcv, timeout_of m c = Some t -> (0 < t * 1000000 < max_ulong)%Z ->
  stale m c rcv now = (t * 1000000 <? age_ns rcv now)%Z.
Proof.
  intros c t [r|] T R; unfold stale; rewrite timeout_ns_agrees, T; auto.
  simpl. symmetry. apply Z.ltb_lt. rewrite ulong_max_agrees. unfold max_ulong in *. lia.
Qed.

Lemma fallback_run:
  forall ir, In ir (filter (has_fallback m) (nm_inrels m)) -> item_run (inl ir).
Proof.
  intros ir Hir le mm u Hle Fr G Hu. apply filter_In in Hir. destruct Hir as [Hir HF].
  specialize (Hle (reads_age_fallback m ir Hir HF)) as Hnow.
  unfold has_fallback in HF. destruct (find_assoc (ir_input ir) (nm_fallbacks m)) as [fv|] eqn:F; [|discriminate].
  destruct (fallback_topic ir fv Hir F) as (tp & t & Ht & Ec & TO & Tv & Rt).
  destruct (wf_fallback m (ir_input ir) fv W (find_assoc_In _ _ _ _ F)) as (q & _ & _ & I & _).
  assert (Pq: inrel_prim (make_tables m) ir = q).
  { unfold inrel_prim. rewrite (scalar_input_elem ir q Hir I). eapply input_prim_tables; eauto; reflexivity. }
  rewrite Pq in Tv.
  set (age := age_ns (snd (ck (ir_topic ir))) now).
  set (le1 := set_assoc age_temp (Vlong age) le).
  assert (X1: exec_stmt ctx ge [] le mm w (age_stmt (ir_topic ir)) [] le1 mm w Out_normal).
  { unfold le1, age. rewrite <- Ec. apply age_run; auto. }
  assert (Hle1: le_ok le1) by (apply le_ok_set; auto; intro E; discriminate).
  assert (Ra := age_ns_range (snd (ck (ir_topic ir))) now).
  assert (EC: eval_expr ge [] le1 mm (stale_expr t)
              = Some (Vint (if stale m (ir_topic ir) (snd (ck (ir_topic ir))) now then 1 else 0))).
  { rewrite (stale_age _ t _ TO Rt). unfold stale_expr. cbn [eval_expr typeof]. simpl binop_type.
    unfold le1. rewrite find_assoc_set_same. simpl. fold age.
    rewrite (wrap_ulong (t * 1000000)) by (unfold max_ulong in *; lia).
    unfold int_binop. rewrite (in_range_ulong (t * 1000000)) by (unfold max_ulong in *; lia).
    rewrite (in_range_ulong age) by exact Ra. reflexivity. }
  unfold item_stmt, fallback_stmt. rewrite F, TO.
  unfold item_val, item_field. rewrite F.
  destruct (stale m (ir_topic ir) (snd (ck (ir_topic ir))) now) eqn:S.
  - destruct (exec_store_input le1 mm u (ir_input ir) q (const_of q fv) fv I G Hu
                (eval_const_of le1 mm q fv Tv) Tv) as (mm' & u' & X2 & G' & Hu' & Sv & N' & O').
    exists le1, mm', u'. repeat split; auto.
    + change (@nil event) with (@nil event ++ @nil event). eapply exec_Sseq_1; [exact X1|].
      eapply exec_Sifthenelse; [exact EC|reflexivity|]. simpl.
      rewrite (input_dst_scalar ir q Hir I), Pq. exact X2.
    + destruct Fr as [Fn Fo]. congruence.
    + intros b' N. destruct Fr as [Fn Fo]. rewrite O' by auto. auto.
    + eapply mval_get_set_same; eauto.
    + intros y N. eapply mval_get_set_disjoint; eauto. simpl. left. congruence.
  - exists le1, mm, u. repeat split; auto; try apply Fr.
    change (@nil event) with (@nil event ++ @nil event). eapply exec_Sseq_1; [exact X1|].
    eapply exec_Sifthenelse; [exact EC|reflexivity|]. simpl. apply exec_Sskip.
Qed.

Lemma derived_run:
  forall dr, In dr (nm_drels m) -> item_run (inr dr).
Proof.
  intros dr Hdr le mm u Hle Fr G Hu.
  destruct (drel_topic dr Hdr) as (tp & Ht & Ec & Pq).
  destruct (wf_drel m dr W Hdr) as (tp' & _ & _ & I).
  unfold item_stmt, item_val, item_field, derived_stmt, derived_value. rewrite uint_max_agrees.
  assert (FR: forall mm' u', fr mm' -> get_block mm' bu = Some (UT, u') -> mval_has_type ce UT u' ->
            forall v, mval_set u [Sfield (dr_input dr)] (MVscalar v) = Some u' ->
            mval_get u' [Sfield (dr_input dr)] = Some (MVscalar v)
            /\ (forall y, y <> dr_input dr -> mval_get u' [Sfield y] = mval_get u [Sfield y])).
  { intros mm' u' _ _ _ v Sv. split; [eapply mval_get_set_same; eauto|].
    intros y N. eapply mval_get_set_disjoint; eauto. simpl. left. congruence. }
  assert (FRM: forall mm', mem_next mm' = mem_next mm -> (forall b', b' <> bu -> get_block mm' b' = get_block mm b') -> fr mm').
  { intros mm' N O. destruct Fr as [Fn Fo]. split; [congruence|]. intros b' Nb. rewrite O by auto. auto. }
  (* is_new and received: a flag copied through [_t_uchar] *)
  assert (FLAG: forall v e, derived_prim (dr_kind dr) = Pbool ->
            val_has_type v (ctype_of_prim Pbool) -> eval_expr ge [] le mm e = Some v ->
            exists le' mm' u',
               exec_stmt ctx ge [] le mm w (copy Pbool (derived_dst m (make_tables m) dr) e) [] le' mm' w Out_normal
            /\ le_ok le' /\ fr mm' /\ get_block mm' bu = Some (UT, u') /\ mval_has_type ce UT u'
            /\ mval_get u' [Sfield (dr_input dr)] = Some (MVscalar v)
            /\ (forall y, y <> dr_input dr -> mval_get u' [Sfield y] = mval_get u [Sfield y])).
  { intros v e KP Tv E. rewrite KP in I.
    assert (Tp: type_at ce UT [Sfield (dr_input dr)] = Some (ctype_of_prim Pbool)).
    { cbn [type_at]. rewrite type_step_field, (field_type_inputs m W _ _ I). auto. }
    assert (Hx: mval_has_type ce (ctype_of_prim Pbool) (MVscalar v)) by (constructor; auto).
    destruct (store_typed ce mm bu UT u [Sfield (dr_input dr)] _ _ G Hu Tp Hx) as (mm' & u' & S & Sv & G' & Hu' & N' & O').
    exists (set_assoc (temp_name Pbool) v le), mm', u'.
    destruct (FR mm' u' (FRM mm' N' O') G' Hu' v Sv) as [A B].
    refine (conj _ (conj _ (conj _ (conj _ (conj _ (conj A B)))))); auto.
    + eapply exec_copy; eauto.
      * change [Sfield (dr_input dr)] with ([] ++ [Sfield (dr_input dr)]). eapply eval_lvalue_field; [reflexivity|].
        unfold in_var_expr. eapply eval_lvalue_global_struct; eauto.
      * unfold derived_dst. simpl. rewrite Pq, KP. auto.
    + apply le_ok_set; auto. discriminate. }
  destruct (dr_kind dr) eqn:K.
  - (* is_new *)
    apply FLAG; [try rewrite K; reflexivity|destruct (fst (ck (dr_topic dr))); reflexivity|].
    rewrite <- Ec. apply eval_new; auto.
  - (* received *)
    apply FLAG; [try rewrite K; reflexivity|destruct (snd (ck (dr_topic dr))); reflexivity|].
    rewrite <- Ec. apply eval_rcvd; auto.
  - (* age_ms *)
    set (age := age_ns (snd (ck (dr_topic dr))) now).
    set (le1 := set_assoc age_temp (Vlong age) le).
    assert (X1: exec_stmt ctx ge [] le mm w (age_stmt (dr_topic dr)) [] le1 mm w Out_normal).
    { unfold le1, age. rewrite <- Ec. apply age_run; auto. apply Hle. apply (reads_age_derived m dr Hdr K). }
    assert (Hle1: le_ok le1) by (apply le_ok_set; auto; intro E; discriminate).
    assert (Ra := age_ns_range (snd (ck (dr_topic dr))) now). fold age in Ra.
    set (v := Vint (Z.min (age / 1000000) max_uint)).
    assert (Tv: val_has_type v (ctype_of_prim Puint32)).
    { unfold v. simpl. unfold norm_int, wrap, wrap_unsigned. apply Z.mod_small.
      unfold max_uint. change (2 ^ bitsize I32)%Z with 4294967296%Z.
      assert (0 <= age / 1000000)%Z by (apply Z.div_pos; lia). lia. }
    simpl in I.
    destruct (exec_store_input le1 mm u (dr_input dr) Puint32
                (if (age <=? max_age_ns)%Z
                 then Ecast (Ebinop Odiv (Etempvar age_temp tulong) (Econst_long 1000000 tulong) tulong) tuint
                 else Econst_int max_uint tuint) (Vint (Z.min (age / 1000000) max_uint)) I G Hu)
      as (mm' & u' & X2 & G' & Hu' & Sv & N' & O'); auto.
    { rewrite <- age_ms_sat by lia.
      destruct (Z.leb_spec age max_age_ns) as [L|L].
      - cbn [eval_expr typeof]. simpl binop_type. unfold le1. rewrite find_assoc_set_same. simpl.
        replace (wrap_unsigned 64 1000000) with 1000000%Z by reflexivity.
        replace (in_range 64 Unsigned 1000000) with true by reflexivity.
        unfold int_binop. rewrite (in_range_ulong age Ra). simpl.
        rewrite wrap_ulong.
        + simpl. f_equal. f_equal. rewrite Z.quot_div_nonneg by lia.
          unfold norm_int, wrap, wrap_unsigned. apply Z.mod_small.
          change (2 ^ bitsize I32)%Z with 4294967296%Z. unfold max_age_ns in L.
          split; [apply Z.div_pos; lia|]. apply Z.div_lt_upper_bound; lia.
        + rewrite Z.quot_div_nonneg by lia. split; [apply Z.div_pos; lia|].
          unfold max_ulong in *. apply Z.div_le_upper_bound; lia.
      - reflexivity. }
    destruct (FR mm' u' (FRM mm' N' O') G' Hu' _ Sv) as [A B].
    exists le1, mm', u'. refine (conj _ (conj _ (conj _ (conj _ (conj _ (conj _ B)))))); auto.
    + change (@nil event) with (@nil event ++ @nil event). eapply exec_Sseq_1; [exact X1|].
      eapply exec_Sifthenelse.
      * cbn [eval_expr typeof]. simpl binop_type. unfold le1. rewrite find_assoc_set_same. simpl.
        replace (wrap_unsigned 64 max_age_ns) with max_age_ns by reflexivity.
        replace (in_range 64 Unsigned max_age_ns) with true by reflexivity.
        unfold int_binop. rewrite (in_range_ulong age Ra). simpl. reflexivity.
      * reflexivity.
      * unfold derived_dst, in_var_expr in *. rewrite Pq in *. simpl. revert X2.
        destruct (age <=? max_age_ns)%Z; simpl; auto.
Qed.

(** The items, in order. *)
Lemma exec_items:
  forall (L : list (inrel + drel)) le mm u,
  le_ok le -> fr mm -> get_block mm bu = Some (UT, u) -> mval_has_type ce UT u ->
  (forall a, In a L -> item_run a) -> NoDup (map item_field L) ->
  exists le' mm' u',
     exec_stmt ctx ge [] le mm w (seq_of (map item_stmt L)) [] le' mm' w Out_normal
  /\ le_ok le' /\ fr mm' /\ get_block mm' bu = Some (UT, u') /\ mval_has_type ce UT u'
  /\ (forall a, In a L -> mval_get u' [Sfield (item_field a)]
        = match item_val a with Some v => Some (MVscalar v) | None => mval_get u [Sfield (item_field a)] end)
  /\ (forall y, ~ In y (map item_field L) -> mval_get u' [Sfield y] = mval_get u [Sfield y]).
Proof.
  induction L as [|a L IH]; intros le mm u Hle Fr G Hu R NDL.
  - exists le, mm, u. repeat split; auto; try apply Fr.
    + apply exec_Sskip.
    + intros a [].
  - destruct (R a (or_introl eq_refl) le mm u Hle Fr G Hu) as (le1 & mm1' & u1 & X1 & Hle1 & Fr1 & G1 & Hu1 & Set1 & Keep1).
    simpl in NDL. inversion NDL as [|? ? Hn NDL']; subst.
    destruct (IH le1 mm1' u1 Hle1 Fr1 G1 Hu1) as (le' & mm' & u' & X & Hle' & Fr' & G' & Hu' & Set' & Keep'); auto.
    { intros; apply R; simpl; auto. }
    exists le', mm', u'. repeat split; auto; try apply Fr'.
    + simpl. change (@nil event) with (@nil event ++ @nil event). eapply exec_Sseq_1; eauto.
    + intros a' [<-|Ha'].
      * rewrite Keep' by auto. exact Set1.
      * rewrite Set'; auto. destruct (item_val a'); auto.
        apply Keep1. intros E. apply Hn. rewrite <- E. apply in_map; auto.
    + intros y Ny. simpl in Ny. rewrite Keep' by tauto. apply Keep1. intros E; apply Ny; auto.
Qed.

End FRESH.

(** [c_new = 0;] for the timed topics [L]. *)
Lemma resets_run:
  forall (CS : Type) (ctx : ros_context CS) (w : world CS) L le mm,
  incl L (timed m) -> globals_typed p mm ->
  exists mm',
     exec_stmt ctx ge [] le mm w (seq_of (map reset_stmt L)) [] le mm' w Out_normal
  /\ globals_typed p mm'
  /\ globals_changed p mm mm' (map (fun tp => (new_var (tp_cname tp), MVscalar (Vint 0))) L).
Proof.
  intros CS ctx w L; induction L as [|tp L IH]; intros le mm Inc GT.
  - exists mm. repeat split; auto. apply exec_Sskip. constructor.
  - assert (Ht: In tp (timed m)) by (apply Inc; simpl; auto).
    destruct (generate_clock_globals m p tp GEN Ht) as (_ & Fn & _).
    destruct (gen_global_block mm _ _ GT Fn) as (bn & vn & Vn & Gn).
    destruct (exec_assign_global CS ctx w le mm (new_var (tp_cname tp)) bn _ vn (Econst_int 0 tflag) (Vint 0)
                Vn Gn eq_refl eq_refl eq_refl) as (mm2 & X2 & O2 & _).
    assert (GT2: globals_typed p mm2).
    { eapply globals_typed_changed; eauto. intros b ty V. rewrite Vn in V; inversion V; subst.
      constructor; auto. reflexivity. }
    destruct (IH le mm2 (fun x H => Inc x (or_intror H)) GT2) as (mm' & X & GT' & GC).
    exists mm'. repeat split; auto.
    + simpl. change (@nil event) with (@nil event ++ @nil event). eapply exec_Sseq_1; eauto.
    + simpl. econstructor; eauto.
Qed.

(** A direct input relation's topic is not timed, so its input has no
    fallback. *)
Lemma direct_not_timed:
  forall ir, is_direct m ir = true -> is_timed m (ir_topic ir) = false.
Proof.
  intros ir D. unfold is_direct in D. apply andb_true_iff in D as [_ D]. apply negb_true_iff; auto.
Qed.

Lemma direct_no_fallback:
  forall ir, In ir (nm_inrels m) -> is_direct m ir = true -> find_assoc (ir_input ir) (nm_fallbacks m) = None.
Proof.
  intros ir Hir D. destruct (find_assoc (ir_input ir) (nm_fallbacks m)) as [fv|] eqn:F; auto.
  destruct (fallback_topic ir fv Hir F) as (tp & t & Ht & Ec & _).
  generalize (gen_timed_is tp Ht). rewrite Ec, (direct_not_timed ir D). discriminate.
Qed.

Lemma generate_input_glue_ddc_aux: input_glue_ddc m p.
Proof.
  destruct (generate_input_glue m p GEN) as (f & Ff & Fret & Fpar & Fvars & Fbody & _ & _ & Ftemps).
  exists f. split; [apply gen_funct; auto|].
  intros mm ck GT CK.
  destruct (generate_externals m p GEN) as (_ & _ & _ & _ & _ & _ & Fu & _).
  destruct (gen_var _ _ Fu) as [bu Vu].
  destruct (GT _ _ _ Vu) as (u0 & Gu & Hu0). rewrite gen_types in Hu0.
  apply quiet_call_at_intro with (le := create_undef_temps (fn_temps f)); auto.
  - unfold function_entry. rewrite Fvars, Fpar. reflexivity.
  - intros CS ctx w.
    destruct (input_body mm bu GT Vu CS ctx w (create_undef_temps (fn_temps f)) u0 Gu Hu0)
      as (le1 & mm1 & u1 & X1 & G1 & U1 & Hu1 & Rel1 & Dir1).
    assert (GI: global_inputs m p mm = u0) by (unfold global_inputs, global_value; rewrite Vu, Gu; auto).
    assert (X1': exec_stmt ctx ge [] (create_undef_temps (fn_temps f)) mm w (input_base m) [] le1 mm1 w Out_normal).
    { unfold input_base, gen_list_controller_expr_input_glue, gen_list_global_expr_input_glue.
      rewrite copies_map. exact X1. }
    assert (OG1: only_global_changed p mm mm1 (nm_in_var m) u1) by (exists bu, (Tstruct (nm_in_struct m)); auto).
    assert (CK1: forall tp, In tp (timed m) ->
              clock_held p mm1 (tp_cname tp) (fst (ck (tp_cname tp))) (snd (ck (tp_cname tp)))).
    { intros tp Ht. destruct (CK tp Ht) as (A & B & C).
      destruct (generate_clock_globals m p tp GEN Ht) as (Ft & Fn & Fr).
      assert (KEEP: forall x ty, In x (clock_names tp) -> find_def p x = Some (Gvar ty) ->
                global_value p mm1 x = global_value p mm x).
      { intros x ty Hx F. destruct (gen_var _ _ F) as [bx V]. unfold global_value. rewrite V.
        destruct U1 as [_ O]. rewrite O; auto.
        assert (Nx: x <> nm_in_var m).
        { intros ->. destruct (wf_controller_vars_fresh m W) as (_ & NU & _). apply NU.
          eapply clock_name_in_after; eauto. }
        eapply globalenv_vars_disjoint; eauto. }
      split; [|split].
      - rewrite (KEEP _ _ (or_intror (or_introl eq_refl)) Fn). auto.
      - rewrite (KEEP _ _ (or_intror (or_intror (or_introl eq_refl))) Fr). auto.
      - intros t E. rewrite (KEEP _ _ (or_introl eq_refl) Ft). auto. }
    assert (GT1: globals_typed p mm1).
    { apply (globals_typed_changed mm mm1 (nm_in_var m) u1 GT OG1). intros b ty V. rewrite Vu in V; inversion V; subst; auto. }
    (* the input relations fed by a copy, and the derived inputs *)
    assert (FEDV: forall u, (forall ir, In ir (nm_inrels m) -> find_assoc (ir_input ir) (nm_fallbacks m) = None ->
                                mval_get u [Sfield (ir_input ir)] = mval_get u1 [Sfield (ir_input ir)]) ->
                  (forall ir, In ir (nm_inrels m) -> forall fv, find_assoc (ir_input ir) (nm_fallbacks m) = Some fv ->
                     mval_get u [Sfield (ir_input ir)]
                     = if stale m (ir_topic ir) (snd (ck (ir_topic ir))) (w_time w) then Some (MVscalar fv)
                       else mval_get u1 [Sfield (ir_input ir)]) ->
                  forall ir, In ir (glue_inrels m) ->
                  exists g v, global_value p mm (msg_var (ir_topic ir)) = Some g
                    /\ mval_get g (path_steps (ir_path ir)) = Some (MVscalar v)
                    /\ mval_get u (Sfield (ir_input ir) :: path_steps (ir_elem ir))
                       = Some (MVscalar (fed_value m ir v (snd (ck (ir_topic ir))) (w_time w)))).
    { intros u KEEP SET ir Hir. destruct (Rel1 ir Hir) as (g & v & GV & Gg & Gu1).
      apply incl_glue_inrels in Hir.
      exists g, v. repeat split; auto. unfold fed_value.
      destruct (find_assoc (ir_input ir) (nm_fallbacks m)) as [fv|] eqn:F.
      - destruct (wf_fallback m (ir_input ir) fv W (find_assoc_In _ _ _ _ F)) as (q & _ & _ & I & _).
        rewrite (scalar_input_elem ir q Hir I) in Gu1 |- *. change (path_steps []) with (@nil step) in Gu1 |- *.
        rewrite (SET ir Hir fv F). destruct (stale m (ir_topic ir) (snd (ck (ir_topic ir))) (w_time w)); auto.
      - change (Sfield (ir_input ir) :: path_steps (ir_elem ir))
          with ([Sfield (ir_input ir)] ++ path_steps (ir_elem ir)) in Gu1 |- *.
        rewrite mval_get_app in Gu1 |- *. rewrite (KEEP ir Hir F), Gu1. destruct (stale _ _ _ _); auto. }
    rewrite Fbody. destruct (timed m) as [|tp0 l] eqn:TM.
    + (* no timed topic: no fallback, no derived input *)
      assert (NF: nm_fallbacks m = []).
      { destruct (nm_fallbacks m) as [|[x fv] l'] eqn:E; auto. exfalso.
        assert (Hin: In (x, fv) (nm_fallbacks m)) by (rewrite E; simpl; auto).
        destruct (wf_fallback m x fv W Hin) as (q & ir & t & _ & _ & Hir & Ex & _).
        subst x. assert (F: exists fv', find_assoc (ir_input ir) (nm_fallbacks m) = Some fv').
        { rewrite E. simpl. destruct (string_dec (ir_input ir) (ir_input ir)); [eauto|congruence]. }
        destruct F as (fv' & F). destruct (fallback_topic ir fv' Hir F) as (tp & _ & Ht & _).
        rewrite TM in Ht; contradiction. }
      assert (NDR: nm_drels m = []).
      { destruct (nm_drels m) as [|dr l'] eqn:E; auto. exfalso.
        destruct (drel_topic dr) as (tp & Ht & _); [rewrite E; simpl; auto|].
        rewrite TM in Ht; contradiction. }
      exists le1, mm1. split; auto.
      exists u1. split; [econstructor; [exact OG1|constructor]|].
      rewrite gen_types. split; auto. split; [|split].
      * apply FEDV; auto. intros ir _ fv F. rewrite NF in F. discriminate.
      * intros dr Hdr. rewrite NDR in Hdr. contradiction.
      * intros ir Hir D. rewrite GI. apply Dir1; auto.
    + (* timed topics *)
      rewrite <- TM. rewrite <- TM in CK1, CK.
      assert (NE: timed m <> []) by congruence.
      (* the cycle's time, read if some age is *)
      set (le2 := if reads_age m then set_assoc now_temp (Vlong (clock (w_time w))) le1 else le1).
      assert (X2: forall rest t le' mm',
                 exec_stmt ctx ge [] le2 mm1 w (seq_of rest) t le' mm' w Out_normal ->
                 exec_stmt ctx ge [] le1 mm1 w (seq_of ((if reads_age m then [now_call now_temp] else []) ++ rest))
                           t le' mm' w Out_normal).
      { intros rest t le' mm' X. unfold le2 in X. destruct (reads_age m); [|exact X].
        apply (exec_seq_cons ctx ge) with (set_assoc now_temp (Vlong (clock (w_time w))) le1) mm1 w; auto.
        apply exec_now_call; auto. }
      set (L := map inl (filter (has_fallback m) (nm_inrels m)) ++ map inr (nm_drels m)).
      assert (NDL: NoDup (map item_field L)).
      { apply (NoDup_map_inv (fun x => (x, @nil pstep))). rewrite map_map.
        assert (E: map (fun a => (item_field a, @nil pstep)) L
                   = map (fun ir => (ir_input ir, ir_elem ir)) (filter (has_fallback m) (nm_inrels m))
                     ++ map (fun dr => (dr_input dr, @nil pstep)) (nm_drels m)).
        { unfold L. rewrite map_app, !map_map. f_equal. apply map_ext_in. intros ir Hx.
          apply filter_In in Hx. destruct Hx as [Hir HF]. unfold has_fallback in HF.
          destruct (find_assoc (ir_input ir) (nm_fallbacks m)) as [fv|] eqn:F; [|discriminate].
          destruct (wf_fallback m (ir_input ir) fv W (find_assoc_In _ _ _ _ F)) as (q & _ & _ & I & _).
          cbn [item_field]. rewrite (scalar_input_elem ir q Hir I). reflexivity. }
        rewrite E.
        generalize (wf_fed_nodup m W). unfold fed_list. intros N.
        apply NoDup_app_inv in N. destruct N as (N1 & N2 & D).
        apply NoDup_app_intro.
        - apply (NoDup_map_filter _ _ (fun ir => (ir_input ir, ir_elem ir))); auto.
        - exact N2.
        - intros x Hx. apply in_map_iff in Hx. destruct Hx as (ir & <- & Hx). apply filter_In in Hx.
          apply D. apply (in_map (fun ir => (ir_input ir, ir_elem ir))); tauto. }
      assert (RUN: forall a, In a L -> item_run ctx w mm1 bu ck a).
      { intros a Ha. unfold L in Ha. apply in_app_iff in Ha. destruct Ha as [Ha|Ha];
          apply in_map_iff in Ha; destruct Ha as (r & <- & Hr);
          [apply (fallback_run ctx w mm1 bu ck Vu CK1)|apply (derived_run ctx w mm1 bu ck Vu CK1)]; auto. }
      assert (Fr1: frame mm1 bu mm1) by (split; auto).
      assert (Hle2: reads_age m = true -> find_assoc now_temp le2 = Some (Vlong (clock (w_time w))))
        by (intros R; unfold le2; rewrite R; apply find_assoc_set_same).
      destruct (exec_items ctx w mm1 bu ck L le2 mm1 u1 Hle2 Fr1 G1 Hu1 RUN NDL)
        as (le3 & mm3 & u3 & X3 & _ & Fr3 & G3 & Hu3 & Set3 & Keep3).
      assert (OG3: only_global_changed p mm mm3 (nm_in_var m) u3).
      { exists bu, (Tstruct (nm_in_struct m)). split; auto. split; auto.
        destruct U1 as [N1 O1], Fr3 as [N3 O3]. split; [congruence|]. intros b' Nb. rewrite O3, O1; auto. }
      assert (GT3: globals_typed p mm3).
      { apply (globals_typed_changed mm mm3 (nm_in_var m) u3 GT OG3). intros b ty V. rewrite Vu in V; inversion V; subst; auto. }
      destruct (resets_run CS ctx w (timed m) le3 mm3 (incl_refl _) GT3) as (mm4 & X4 & _ & GC4).
      exists le3, mm4. split.
      * change (@nil event) with (@nil event ++ @nil event). eapply exec_Sseq_1; [exact X1'|].
        unfold timed_stmts. apply X2.
        rewrite app_assoc.
        replace (map (fallback_stmt m (make_tables m)) (filter (has_fallback m) (nm_inrels m))
                 ++ map (derived_stmt m (make_tables m)) (nm_drels m))
          with (map item_stmt L)
          by (unfold L; rewrite map_app, !map_map; reflexivity).
        change (@nil event) with (@nil event ++ @nil event).
        eapply exec_seq_of_app; [exact X3|exact X4].
      * assert (KEEP3: forall ir, In ir (nm_inrels m) -> find_assoc (ir_input ir) (nm_fallbacks m) = None ->
                  mval_get u3 [Sfield (ir_input ir)] = mval_get u1 [Sfield (ir_input ir)]).
        { intros ir Hir F. apply Keep3. unfold L. rewrite map_app, !map_map, in_app_iff. cbn [item_field].
              intros [Hx|Hx]; apply in_map_iff in Hx.
              ** destruct Hx as (ir' & E & Hir'). apply filter_In in Hir'. destruct Hir' as [Hir' HF].
                 unfold has_fallback in HF. rewrite E, F in HF. discriminate.
              ** destruct Hx as (dr & E & Hdr). generalize (wf_fed_nodup m W). unfold fed_list. intros N.
                 apply NoDup_app_inv in N. destruct N as (_ & _ & D).
                 destruct (wf_drel m dr W Hdr) as (_ & _ & _ & I). rewrite E in I.
                 apply (D (ir_input ir, ir_elem ir)).
                 --- apply (in_map (fun ir => (ir_input ir, ir_elem ir))); auto.
                 --- rewrite (scalar_input_elem ir _ Hir I), <- E.
                     apply (in_map (fun dr => (dr_input dr, @nil pstep))); auto. }
        exists u3. split; [econstructor; eauto|]. rewrite gen_types. split; auto. split; [|split].
        -- apply FEDV.
           ++ exact KEEP3.
           ++ intros ir Hir fv F.
              assert (Ha: In (inl ir) L).
              { unfold L. apply in_app_iff. left. apply in_map. apply filter_In. split; auto.
                unfold has_fallback. rewrite F; auto. }
              generalize (Set3 _ Ha). cbn [item_val item_field]. rewrite F. intros ->.
              destruct (stale m (ir_topic ir) (snd (ck (ir_topic ir))) (w_time w)); auto.
        -- intros dr Hdr. assert (Ha: In (inr dr) L) by (unfold L; apply in_app_iff; right; apply in_map; auto).
           generalize (Set3 _ Ha). cbn [item_val item_field]. intros ->. reflexivity.
        -- intros ir Hir D. rewrite GI, <- (Dir1 ir Hir D). unfold input_leaf.
           change (Sfield (ir_input ir) :: path_steps (ir_elem ir))
             with ([Sfield (ir_input ir)] ++ path_steps (ir_elem ir)).
           rewrite !mval_get_app, KEEP3; auto. apply direct_no_fallback; auto.
Qed.


(** ** Direct input relations (rule 4.16) *)

Section DIRECT.

Variable tp : topic.
Hypothesis Htp : In tp (subscribed m).

Variables (mm : mem) (b bu : block) (mv : mval).
Hypothesis Vu : find_var ge (nm_in_var m) = Some (bu, Tstruct (nm_in_struct m)).
Hypothesis Gb : get_block mm b = Some (Tstruct (tp_msg tp), mv).
Hypothesis Hmv : mval_has_type ce (Tstruct (tp_msg tp)) mv.
Hypothesis Nb : b <> bu.

Let le_ok (le : temp_env) : Prop := find_assoc msg_param le = Some (Vptr b []).
Let sv (ir : inrel) : val := scalar_at mv (path_steps (ir_path ir)).
Let srcD (ir : inrel) : expr := path_expr ce (deref_param msg_param (tp_msg tp)) (ir_path ir).

Lemma direct_le_ok_set: forall le q v, le_ok le -> le_ok (set_assoc (temp_name q) v le).
Proof.
  intros le q v H. unfold le_ok. rewrite find_assoc_set_other; auto.
  intros E; apply (proj1 (temp_name_not_param q)); auto.
Qed.

(** The message leaf of a direct relation of [tp], in the message [mv]. *)
Lemma direct_source:
  forall ir, In ir (direct_of m (tp_cname tp)) ->
  exists t q x,
     In ir (nm_inrels m)
  /\ find_assoc (ir_input ir) (nm_inputs m) = Some t
  /\ ctrl_prim t (ir_elem ir) = Some q
  /\ resolve msgs (FTmsg (tp_msg tp)) (ir_path ir) = Some (FTprim q)
  /\ inrel_prim (make_tables m) ir = q
  /\ mval_get mv (path_steps (ir_path ir)) = Some (MVscalar x)
  /\ val_has_type x (ctype_of_prim q)
  /\ sv ir = x.
Proof.
  intros ir Hd. apply direct_of_In in Hd as (Hir & Ec & _).
  destruct (input_exprs m ir W Hir) as (tp' & t & q & F & _ & _ & I & Q & R & Pq & _ & _).
  assert (Ht: In tp (nm_topics m)) by (apply in_subscribed in Htp; tauto).
  rewrite Ec, (In_find_topic _ _ (wf_cnames_nodup m W) Ht) in F. inversion F; subst tp'.
  destruct (leaf_typed m W _ _ _ mv R Hmv) as (x & Gx & Tx).
  exists t, q, x. repeat split; auto. apply scalar_at_spec; auto.
Qed.

Lemma direct_item_ok:
  forall ir, In ir (direct_of m (tp_cname tp)) ->
  item_ok ge [] ce _ (inrel_prim (make_tables m)) (input_dst m) srcD input_leaf sv le_ok
          mm bu (Tstruct (nm_in_struct m)) ir.
Proof.
  intros ir Hd.
  destruct (direct_source ir Hd) as (t & q & x & Hir & I & Q & R & Pq & Gx & Tx & Sx).
  destruct (input_dst_place bu Vu ir Hir) as (D1 & D2 & D3).
  unfold item_ok. rewrite Pq in *. rewrite Sx. repeat split; auto.
  intros le mm1 Hle [Fn Fo].
  destruct (eval_leaf m W ge [] le mm1 (tp_msg tp) (ir_path ir) q
              (deref_param msg_param (tp_msg tp)) b [] R) as (_ & _ & E); auto.
  { apply eval_lvalue_deref_param; auto. }
  unfold srcD. rewrite E. apply load_spec; [apply ctype_of_prim_scalar_type|].
  unfold load_path. rewrite Fo by auto. rewrite Gb. auto.
Qed.

Lemma direct_body:
  forall (CS : Type) (ctx : ros_context CS) (w : world CS) le u0,
  le_ok le -> get_block mm bu = Some (Tstruct (nm_in_struct m), u0) ->
  mval_has_type ce (Tstruct (nm_in_struct m)) u0 ->
  exists le' mm' u,
     exec_stmt ctx ge [] le mm w
       (seq_of (map (direct_copy m (make_tables m) (tp_msg tp)) (direct_of m (tp_cname tp)))) [] le' mm' w Out_normal
  /\ get_block mm' bu = Some (Tstruct (nm_in_struct m), u)
  /\ mval_has_type ce (Tstruct (nm_in_struct m)) u
  /\ direct_copied m tp mv u0 u
  /\ unchanged_except mm mm' bu.
Proof.
  intros CS ctx w le u0 Hle Gu Hu0.
  destruct (exec_copies ctx ge [] w ce _ (inrel_prim (make_tables m)) (input_dst m) srcD input_leaf sv
              le_ok direct_le_ok_set mm bu (Tstruct (nm_in_struct m)) (direct_of m (tp_cname tp)) le mm u0)
    as (le' & mm' & u & X & _ & Fr & G' & Hu & Set' & Keep'); auto.
  - split; auto.
  - apply direct_item_ok.
  - apply NoDup_map_filter_sub, input_leaves_nodup.
  - intros a1 a2 H1 H2 N. apply direct_of_In in H1 as (H1 & _). apply direct_of_In in H2 as (H2 & _).
    apply input_leaves_disjoint; auto.
  - exists le', mm', u. split; [exact X|]. split; [exact G'|]. split; [exact Hu|].
    split; [|apply frame_unchanged; auto]. split; [|exact Keep'].
    intros ir Hd. rewrite (Set' ir Hd).
    destruct (direct_source ir Hd) as (_ & _ & x & _ & _ & _ & _ & _ & Gx & _ & Sx). rewrite Gx, Sx. reflexivity.
Qed.

End DIRECT.

(** Before any message, the leaf of a direct relation in [Controller_U]
    and the relation's leaf in the zero message agree (both zero). *)
Lemma gen_zero_direct:
  forall tp ir, In tp (subscribed m) -> In ir (direct_of m (tp_cname tp)) ->
  mval_get (zero_mval ce (Tstruct (nm_in_struct m))) (input_leaf ir)
  = mval_get (zero_mval ce (Tstruct (tp_msg tp))) (path_steps (ir_path ir)).
Proof.
  intros tp ir Htp Hd. apply direct_of_In in Hd as (Hir & Ec & _).
  destruct (input_exprs m ir W Hir) as (tp' & t & q & F & _ & _ & I & Q & R & Pq & _ & _).
  assert (Ht: In tp (nm_topics m)) by (apply in_subscribed in Htp; tauto).
  rewrite Ec, (In_find_topic _ _ (wf_cnames_nodup m W) Ht) in F. inversion F; subst tp'.
  rewrite (gen_zero_leaf _ _ _ R), <- Pq.
  apply mval_get_zero; [apply gen_wf_composites| |apply gen_input_leaf_type; auto].
  simpl. apply in_ident_spec. unfold composite_names, composites.
  rewrite map_app, map_map. apply in_or_app; right; simpl; auto.
Qed.

(** Every callback of a subscribed topic copies the leaves that the glue
    keeps of the message it is given into the topic's global, updates
    the topic's clock if it is timed, else writes the leaves of its
    direct input relations into [Controller_U], and changes nothing
    else. *)
Lemma generate_callback_ddc_aux:
  forall tp, In tp (subscribed m) -> callback_ddc m p tp.
Proof.
  intros tp Htp.
  destruct (generate_callback m p tp GEN Htp)
    as [Fv (f & Ff & Fret & Fpar & Fvars & Fbody & _ & _ & _ & _)].
  exists f. split; [apply gen_funct; auto|].
  intros mm b mv GT NG Gb Hmv. rewrite gen_types in Hmv.
  destruct (gen_var _ _ Fv) as [bg Vg].
  destruct (GT _ _ _ Vg) as (g0 & Gg & Hg0). rewrite gen_types in Hg0.
  assert (Nb: b <> bg) by (intros E; apply (NG _ _ _ Vg); auto).
  destruct (generate_externals m p GEN) as (_ & _ & _ & _ & _ & _ & Fu & _).
  destruct (gen_var _ _ Fu) as [bu Vu].
  destruct (GT _ _ _ Vu) as (u0 & Gu & Hu0). rewrite gen_types in Hu0.
  assert (Nbu: b <> bu) by (intros E; apply (NG _ _ _ Vu); auto).
  assert (Ngu: bg <> bu) by (eapply globalenv_vars_disjoint; eauto; apply (proj1 (gen_in_out_vars tp Htp))).
  assert (GI: global_inputs m p mm = u0) by (unfold global_inputs, global_value; rewrite Vu, Gu; auto).
  set (le0 := set_assoc msg_param (Vptr b []) (create_undef_temps (fn_temps f))).
  apply quiet_call_at_intro with (le := le0); auto.
  - unfold function_entry. rewrite Fvars, Fpar. reflexivity.
  - intros CS ctx w.
    destruct (callback_body tp mm b bg mv Vg Gb Hmv Nb CS ctx w le0 g0) as (le' & mm1 & g & X & G' & Tg & RC & U & Hle'); auto.
    { unfold le0. apply find_assoc_set_same. }
    assert (GM: global_msg p mm (tp_cname tp) = g0) by (unfold global_msg, global_value; rewrite Vg, Gg; auto).
    assert (OG1: only_global_changed p mm mm1 (msg_var (tp_cname tp)) g)
      by (exists bg, (Tstruct (tp_msg tp)); auto).
    assert (GT1: globals_typed p mm1).
    { eapply globals_typed_changed; eauto. intros b' ty V. rewrite Vg in V; inversion V; subst; auto. }
    assert (Gu1: get_block mm1 bu = Some (Tstruct (nm_in_struct m), u0)) by (destruct U as [_ O]; rewrite O; auto).
    assert (Gb1: get_block mm1 b = Some (Tstruct (tp_msg tp), mv)) by (destruct U as [_ O]; rewrite O; auto).
    assert (ID: only_global_changed p mm1 mm1 (nm_in_var m) u0)
      by (exists bu, (Tstruct (nm_in_struct m)); repeat split; auto).
    assert (NOD: direct_copied m tp mv u0 u0 \/ direct_of m (tp_cname tp) <> []).
    { destruct (direct_of m (tp_cname tp)) as [|ir0 ds] eqn:D; [left|right; discriminate].
      split; auto. intros ir Hir. rewrite D in Hir. contradiction. }
    rewrite Fbody, gen_types. cbv zeta. unfold clock_update. rewrite GM, GI.
    destruct (is_timed m (tp_cname tp)) eqn:T.
    + assert (Ht: In tp (timed m)) by (apply filter_In; auto).
      destruct (clock_run tp CS ctx w le' mm1 Ht GT1) as (le2 & mm2 & X2 & _ & GC).
      exists le2, mm2. split.
      * change (@nil event) with (@nil event ++ @nil event). eapply exec_Sseq_1; eauto.
      * exists g, u0. split; [econstructor; eauto; econstructor; eauto|].
        repeat split; auto. intros ir Hir. exfalso.
        apply direct_of_In in Hir as (_ & Ec & D). generalize (direct_not_timed ir D).
        rewrite Ec, T. discriminate.
    + destruct (direct_of m (tp_cname tp)) as [|ir0 ds] eqn:D.
      * destruct NOD as [NOD|NOD]; [|congruence].
        exists le', mm1. split; auto. exists g, u0.
        split; [econstructor; eauto; econstructor; eauto; constructor|]. repeat split; auto; apply NOD.
      * destruct (direct_body tp Htp mm1 b bu mv Vu Gb1 Hmv Nbu CS ctx w le' u0 Hle' Gu1 Hu0)
          as (le2 & mm2 & u & X2 & G2 & Hu & DC & U2).
        rewrite D in X2.
        exists le2, mm2. split.
        -- change (@nil event) with (@nil event ++ @nil event). eapply exec_Sseq_1; eauto.
        -- exists g, u. split; [|repeat split; auto; apply DC].
           apply globals_changed_cons with mm1; [exact OG1|].
           apply globals_changed_cons with mm2; [|constructor].
           exists bu, (Tstruct (nm_in_struct m)). split; [exact Vu|]. split; [exact G2|exact U2].
Qed.

End GENERATED.
