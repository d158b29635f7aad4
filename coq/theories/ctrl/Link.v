(** * The linked program: the glue and the generated controller in one semantics *)

(** T2 and T7 treat [Controller_step] as the environment model's
    controller, its state held by the environment ([Environment.w_ctrl]);
    T6 proves that the C generated from a diagram behaves as that model
    requires.  This file removes the seam: [link p d] is *one* program,
    the glue [p] in which the declarations of [Controller_initialize] and
    [Controller_step] are replaced by their generated definitions
    ([Diagramgen.init_function], [step_function]), with the state global
    [Controller_DW] (and its struct) of the diagram, as the C linker joins
    the glue's and the controller's units.  [linked_node_ddc] (T8) states
    T7 for that program in *every* environment (its controller is never
    called): its trace is the registrations of the topics and, in each
    cycle, the publications of the related fields of the diagram's
    outputs, the diagram stepped on the newest inputs from the state its
    previous step left in [Controller_DW].

    The proof is a forward simulation ([Linksim.sim], for every program
    and any controller implementation, in [Linksim]): a run of the glue in the environment
    whose controller is the diagram ([Endtoend.diagram_ctx]) is matched
    step by step by a run of the linked program, in which
    - the state global is block 1 and every block of the glue moves up by
      one ([rbd]; no move when the diagram has no state): memories agree
      up to that renaming ([mrel]), pointers in values too ([rv], [rmv]);
    - the controller's state, held by the glue's environment, is the
      contents of [Controller_DW] ([crel]); each call of the controller
      runs the generated function, whose effect T6 gives ([ctrl_sim]);
    - traces agree once [Einit] and [Estep] are erased ([rtrace]): the
      linked program calls no external controller.
    The semantics being deterministic, the linked program's only run is
    the simulating one.  The state's struct comes after the glue's
    ([state_types]); it changes no value nor conversion of the glue's
    types ([clamp_extend], [default_mval_extend]). *)


From Coq Require Import String List ZArith Bool Lia.
From ROSGen Require Import Maps Errors Syntax Values Operators Memory Environment Semantics.
From ROSGen Require Loopproof.
From ROSGen Require Export Linksim.
Import ListNotations.

(** ** The linked program of a node whose controller is a block diagram *)

From ROSGen Require Import NodeModel Wellformed Generator Generatorspec Generatorproof DDC
                           Diagram Diagramgen Diagramproof Endtoend.

(** [link p d]: the glue [p] linked with the C of the diagram [d]
    ([Diagramgen.dg_program]): the declarations of [Controller_initialize]
    and [Controller_step] are replaced by their generated definitions, and
    the state struct and global [Controller_DW] (when the diagram has
    states) come first.  The inputs and outputs globals are the glue's. *)
Definition link_fundef (d : diagram) (fd : fundef) : fundef :=
  match fd with
  | External (EF_controller_initialize _ _) _ _ => Internal (init_function d)
  | External (EF_controller_step _ _) _ _ => Internal (step_function d)
  | _ => fd
  end.

Definition state_types (d : diagram) : list composite_definition :=
  if has_states d then [state_composite d] else [].

Definition state_defs (d : diagram) : list (ident * globdef) :=
  if has_states d then [(dg_state_var d, Gvar (Tstruct (dg_state_struct d)))] else [].

Definition link (p : program) (d : diagram) : program :=
  mkprogram (prog_types p ++ state_types d) (state_defs d ++ map (ldef (link_fundef d)) (prog_defs p)) (prog_main p).

(** The state global is block 1; the glue's blocks move up by one. *)
Definition dwb : block := 1%positive.
Definition rbd (d : diagram) (b : block) : block := if has_states d then Pos.succ b else b.

Lemma rbd_inj: forall d b1 b2, rbd d b1 = rbd d b2 -> b1 = b2.
Proof. unfold rbd; intros d b1 b2 H. destruct (has_states d); auto. apply Pos.succ_inj; auto. Qed.

Lemma rbd_succ: forall d b, rbd d (Pos.succ b) = Pos.succ (rbd d b).
Proof. unfold rbd; intros d b. destruct (has_states d); auto. Qed.

Lemma dwb_extra: forall d, has_states d = true -> extra (rbd d) dwb.
Proof. unfold extra, rbd, dwb; intros d H b E. rewrite H in E. symmetry in E. apply (Pos.succ_not_1 b E). Qed.

Lemma find_assoc_notin:
  forall (A : Type) x (l : list (ident * A)), ~ In x (map fst l) -> find_assoc x l = None.
Proof. induction l as [|[y a] l IH]; simpl; intros H; auto. destruct (string_dec x y); [subst; tauto|auto]. Qed.

Lemma var_names_fst: forall defs x, In x (var_names defs) -> In x (map fst defs).
Proof.
  induction defs as [|[y g] defs IH]; simpl; intros x H; auto. destruct g; simpl in H; auto.
  destruct H; auto.
Qed.

Lemma globalenv_funct_name:
  forall p x fd, find_funct (globalenv p) x = Some fd -> In x (map fst (prog_defs p)).
Proof.
  intros p x fd F. unfold globalenv, globalenv_mem in F.
  destruct (alloc_globals (mkgenv (prog_types p) [] []) empty (prog_defs p)) as [ge m] eqn:A. simpl in F.
  destruct (alloc_globals_inv _ _ _ _ _ (globals_inv_empty (prog_types p)) A) as (_ & _ & _ & FS & _).
  unfold find_funct in F. rewrite FS, app_nil_r in F. apply find_assoc_In in F.
  apply in_rev, fun_defs_In in F. apply (in_map fst _ _ F).
Qed.

Lemma globalenv_var_name:
  forall p x, ~ In x (map fst (prog_defs p)) -> find_var (globalenv p) x = None.
Proof.
  intros p x N. unfold globalenv, globalenv_mem.
  destruct (alloc_globals (mkgenv (prog_types p) [] []) empty (prog_defs p)) as [ge m] eqn:A. simpl.
  destruct (alloc_globals_inv _ _ _ _ _ (globals_inv_empty (prog_types p)) A) as (_ & _ & VS & _).
  unfold find_var. apply find_assoc_notin. rewrite VS, app_nil_r. intros I. apply in_rev in I.
  apply N, var_names_fst; auto.
Qed.

Section GLOBALENV.

Variables (p : program) (d : diagram).
Hypothesis NDW : ~ In (dg_state_var d) (map fst (prog_defs p)).
Hypothesis NDS : has_states d = true -> ~ In (dg_state_struct d) (composite_names (prog_types p)).
Hypothesis WFC : wf_composites (prog_types p).
Hypothesis CV : forall x ty, In (x, Gvar ty) (prog_defs p) -> complete_type (composite_names (prog_types p)) ty = true.

Local Notation ce := (prog_types p).
Local Notation ceL := (prog_types p ++ state_types d).

Lemma zero_link: forall ty, complete_type (composite_names ce) ty = true -> zero_mval ceL ty = zero_mval ce ty.
Proof.
  intros ty C. unfold state_types. destruct (has_states d) eqn:H.
  - apply default_mval_extend; auto.
  - rewrite app_nil_r; auto.
Qed.

Lemma link_globalenv:
  grel (rbd d) (link_fundef d) (globalenv p) (globalenv (link p d))
  /\ mrel (rbd d) (init_mem p) (init_mem (link p d))
  /\ ge_comp (globalenv (link p d)) = ceL
  /\ (forall x, x <> dg_state_var d -> find_var (globalenv p) x = None -> find_var (globalenv (link p d)) x = None)
  /\ (has_states d = true ->
        find_var (globalenv (link p d)) (dg_state_var d) = Some (dwb, Tstruct (dg_state_struct d))
     /\ get_block (init_mem (link p d)) dwb
        = Some (Tstruct (dg_state_struct d), zero_mval ceL (Tstruct (dg_state_struct d)))).
Proof.
  unfold globalenv, init_mem, globalenv_mem.
  destruct (alloc_globals (mkgenv ce [] []) empty (prog_defs p)) as [ge' m'] eqn:A.
  set (X := if has_states d then [(dg_state_var d, (dwb, Tstruct (dg_state_struct d)))] else []).
  set (mL0 := if has_states d then fst (alloc empty (Tstruct (dg_state_struct d))
                                              (zero_mval ceL (Tstruct (dg_state_struct d)))) else empty).
  assert (E0: alloc_globals (mkgenv (prog_types (link p d)) [] []) empty (prog_defs (link p d))
              = alloc_globals (mkgenv ceL X []) mL0 (map (ldef (link_fundef d)) (prog_defs p))).
  { unfold link, X, mL0, state_defs; simpl. destruct (has_states d); reflexivity. }
  assert (R0: mrel (rbd d) empty mL0).
  { unfold mL0, rbd. destruct (has_states d) eqn:H.
    - destruct (alloc empty (Tstruct (dg_state_struct d)) (zero_mval ceL (Tstruct (dg_state_struct d)))) as [m0 b0] eqn:AL.
      simpl. split.
      + rewrite (alloc_next _ _ _ _ _ AL). reflexivity.
      + intros b. rewrite (get_block_alloc_other _ _ _ _ _ _ AL).
        * rewrite !get_block_empty. reflexivity.
        * rewrite (alloc_result _ _ _ _ _ AL). simpl. intros E. apply (Pos.succ_not_1 b E).
    - split; simpl; auto. intros b. rewrite !get_block_empty. reflexivity. }
  destruct (alloc_globals_link (rbd d) (rbd_inj d) (rbd_succ d) (link_fundef d) X (prog_defs p)
              (mkgenv ce [] []) empty (mkgenv ceL X []) mL0 ge' m' A R0 eq_refl eq_refl)
    as (geL' & mL' & A' & R' & S' & C' & V' & F').
  { intros x ty I. simpl. apply zero_link. eapply CV; eauto. }
  rewrite E0, A'. simpl.
  destruct (alloc_globals_inv _ _ _ _ _ (globals_inv_empty ce) A) as (_ & C1 & VS & FS & _).
  assert (DWnot: find_assoc (dg_state_var d) (ge_vars ge') = None).
  { apply find_assoc_notin. rewrite VS, app_nil_r. intros I. apply in_rev in I. apply NDW, var_names_fst; auto. }
  split; [split|split; [exact R'|split; [rewrite C'; reflexivity|split]]].
  - intros x b ty V. unfold find_var in *. rewrite V'. apply find_assoc_app_some.
    rewrite find_assoc_rvars. simpl in V. rewrite V. reflexivity.
  - intros x fd V F. unfold find_var, find_funct in *. rewrite V'. rewrite find_assoc_app_none.
    + unfold X. destruct (has_states d); auto. simpl. destruct (string_dec x (dg_state_var d)); auto.
      subst. exfalso. apply NDW. apply (globalenv_funct_name p) with fd.
      unfold globalenv, globalenv_mem. rewrite A. exact F.
    + rewrite find_assoc_rvars. simpl in V. rewrite V. reflexivity.
  - intros x fd F. unfold find_funct in *. rewrite F'. rewrite find_assoc_lfuns. simpl in F. rewrite F. reflexivity.
  - intros x N V. unfold find_var in *. rewrite V'. rewrite find_assoc_app_none.
    + unfold X. destruct (has_states d); auto. simpl. destruct (string_dec x (dg_state_var d)); auto. contradiction.
    + rewrite find_assoc_rvars. simpl in V. rewrite V. reflexivity.
  - intros H. split.
    + unfold find_var. rewrite V'. rewrite find_assoc_app_none.
      * unfold X. rewrite H. simpl. destruct (string_dec (dg_state_var d) (dg_state_var d)); congruence.
      * rewrite find_assoc_rvars. rewrite DWnot. reflexivity.
    + rewrite S' by (apply dwb_extra; auto). unfold mL0. rewrite H. unfold get_block; simpl. reflexivity.
Qed.

End GLOBALENV.

(** ** Facts on the generated glue *)

Section GENERATED.

Variable m : node_model.
Variable p : program.
Hypothesis GEN : generate m = OK p.

Let ND : NoDup (map fst (prog_defs p)) := generate_names_distinct m p GEN.

(** The functions of the glue: only [loop] has locals (a message of a
    published topic each); the external functions name the topics'
    messages and the controller's globals. *)
Lemma gen_fundef:
  forall x fd, find_funct (globalenv p) x = Some fd ->
  (forall f, fd = Internal f -> forall y ty, In (y, ty) (fn_vars f) ->
     exists tp, In tp (published m) /\ ty = Tstruct (tp_msg tp))
  /\ (forall ef targs tres, fd = External ef targs tres ->
       match ef with
       | EF_ros_subscribe topic msgty _ => exists tp, In tp (subscribed m) /\ topic = tp_name tp /\ msgty = tp_msg tp
       | EF_ros_publish _ msgty => exists tp, In tp (nm_topics m) /\ msgty = tp_msg tp
       | EF_controller_initialize u y | EF_controller_step u y =>
           u = nm_in_var m /\ y = nm_out_var m /\ targs = [] /\ tres = Tvoid
       | _ => True
       end).
Proof.
  intros x fd F. apply find_funct_globalenv in F; auto.
  apply (find_def_build m p x _ GEN) in F.
  unfold build_defs in F. rewrite !in_app_iff in F.
  destruct F as [V|[V|[V|[V|[V|[V|[V|[V|V]]]]]]]].
  - unfold ros_externals, time_externals, now_externals, stamp_externals in V.
    split; [intros f E; subst; destruct (timed m), (nm_stamps m); simpl in V; intuition discriminate|].
    intros ef targs tres E. subst.
    destruct (timed m), (nm_stamps m); simpl in V; intuition (try inversion H; try inversion H0; subst; auto).
  - apply in_flat_map in V; destruct V as (tp & Htp & V).
    unfold topic_externals in V; destruct (tp_dir tp) eqn:Dir; simpl in V.
    + destruct V as [V|[]]; inversion V; subst. split; [intros f E; discriminate|].
      intros ef targs tres E; inversion E; subst. exists tp. split; [apply in_subscribed; auto | auto].
    + destruct V as [V|[V|[]]]; inversion V; subst; (split; [intros f E; discriminate|]);
        intros ef targs tres E; inversion E; subst; eauto.
  - simpl in V. destruct V as [V|[V|[V|[V|[]]]]]; inversion V; subst;
      (split; [intros f E; discriminate|]); intros ef targs tres E; inversion E; subst; auto.
  - apply in_map_iff in V; destruct V as (tp & E & _); discriminate.
  - apply in_flat_map in V. destruct V as (tp & _ & V). simpl in V.
    destruct V as [V|[V|[V|[]]]]; discriminate.
  - apply in_map_iff in V. destruct V as (tp & E & _). inversion E; subst.
    split; [|intros ef targs tres E'; discriminate].
    intros f E' y ty I. inversion E'; subst. unfold callback_function in I.
    destruct (is_timed m (tp_cname tp)); [|destruct (direct_of m (tp_cname tp))]; simpl in I; contradiction.
  - simpl in V. destruct V as [V|[]]. inversion V; subst.
    split; [|intros ef targs tres E'; discriminate].
    intros f E' y ty I. inversion E'; subst. unfold input_glue_function in I.
    destruct (timed m); simpl in I; contradiction.
  - apply in_map_iff in V. destruct V as (tp & E & _). inversion E; subst.
    split; [|intros ef targs tres E'; discriminate].
    intros f E' y ty I. inversion E'; subst. unfold output_glue_function in I.
    destruct (topic_stamp _ _); simpl in I; contradiction.
  - simpl in V. destruct V as [V|[V|[]]]; inversion V; subst;
      (split; [|intros ef targs tres E'; discriminate]); intros f E' y ty I; inversion E'; subst.
    + simpl in I. apply in_map_iff in I. destruct I as (tp & E & I). inversion E; subst. eauto.
    + simpl in I. contradiction.
Qed.

End GENERATED.

(** ** Values without pointers *)

Fixpoint no_ptr (ty : type) : bool :=
  match ty with
  | Tpointer _ => false
  | Tarray t _ => no_ptr t
  | _ => true
  end.

Definition ce_no_ptr (ce : composite_env) : Prop :=
  forall id ms f t, struct_members ce id = Some ms -> In (f, t) ms -> no_ptr t = true.

Lemma rmv_no_ptr:
  forall rb ce, ce_no_ptr ce ->
  forall mv ty, mval_has_type ce ty mv -> no_ptr ty = true -> rmv rb mv = mv.
Proof.
  intros rb ce NP mv. induction mv as [v | fs IH | es IH] using mval_ind2; intros ty H N.
  - inversion H; subst. rewrite rmv_scalar. f_equal. apply (rv_typed rb v ty); auto.
    intros t E; subst; discriminate.
  - inversion H as [| id ms fs' SM FT |]; subst. rewrite rmv_struct. f_equal.
    assert (MN: forall f t, In (f, t) ms -> no_ptr t = true) by (intros; eapply NP; eauto).
    clear SM H. revert ms FT MN. induction IH as [|[g v] fs Hv IHfs IHrec]; intros ms FT MN; [reflexivity|].
    inversion FT as [| f t mv ms' fs'' Hmv Hfs]; subst. unfold rfs in *. simpl. simpl in Hv.
    rewrite (Hv t Hmv (MN g t (or_introl eq_refl))). f_equal. apply (IHrec ms'); auto.
    intros; eapply MN; right; eauto.
  - inversion H as [| | t n es' L ET]; subst. simpl in N. rewrite rmv_array. f_equal.
    clear H. induction IH as [|x es Hx IHes IHrec]; [reflexivity|].
    inversion ET as [| t' mv es'' Hmv Hes]; subst. simpl. rewrite (Hx t Hmv N), IHrec; auto.
Qed.

Lemma no_ptr_prim: forall q, no_ptr (ctype_of_prim q) = true.
Proof. intros []; reflexivity. Qed.

Lemma no_ptr_ftype: forall t, no_ptr (ctype_of_ftype t) = true.
Proof. induction t; simpl; auto. apply no_ptr_prim. Qed.

Lemma composites_no_ptr: forall m, ce_no_ptr (composites m).
Proof.
  intros m id ms f t SM I. unfold struct_members in SM.
  destruct (find_composite id (composites m)) as [co|] eqn:F; [|discriminate]. inversion SM; subst ms.
  unfold find_composite in F. apply find_some in F as [F _].
  unfold composites in F. apply in_app_or in F as [F|F].
  - apply in_map_iff in F as [md [E _]]. subst co. simpl in I.
    apply in_map_iff in I as [[g ft] [E _]]. inversion E; subst. apply no_ptr_ftype.
  - simpl in F. destruct F as [E|[E|[]]]; subst co; simpl in I;
      apply in_map_iff in I as [[g q] [E _]]; inversion E; subst; apply no_ptr_ftype.
Qed.

(** ** The node with its generated controller, linked *)

Section NODE.

Variables (m : node_model) (p : program) (d : diagram).
Hypothesis GEN : generate m = OK p.
Hypothesis WF : dg_wf d = true.
Hypothesis MA : dg_matches m d = true.
Hypothesis FV : ~ In (dg_state_var d) (global_names m).
Hypothesis FS : has_states d = true -> ~ In (dg_state_struct d) (composite_names (composites m)).

Let W : wf_facts m := wf_facts_intro m (generate_sound m p GEN).
Let ND : NoDup (map fst (prog_defs p)) := generate_names_distinct m p GEN.

Local Notation ge := (globalenv p).
Local Notation geL := (globalenv (link p d)).
Local Notation rb := (rbd d).
Local Notation lfd := (link_fundef d).
Local Notation ce := (composites m).
Local Notation ceL := (composites m ++ state_types d).

Lemma TY : prog_types p = ce.
Proof. apply (Gluefacts.gen_types m p GEN). Qed.

Lemma NDW : ~ In (dg_state_var d) (map fst (prog_defs p)).
Proof. rewrite (generate_defs m p GEN), build_defs_names. exact FV. Qed.

Lemma NDS : has_states d = true -> ~ In (dg_state_struct d) (composite_names (prog_types p)).
Proof. rewrite TY. exact FS. Qed.

Lemma WFC : wf_composites (prog_types p).
Proof. rewrite TY. apply (Gluefacts.gen_wf_composites m p GEN). Qed.

Lemma CV : forall x ty, In (x, Gvar ty) (prog_defs p) -> complete_type (composite_names (prog_types p)) ty = true.
Proof.
  intros x ty I. rewrite TY.
  assert (F: find_def p x = Some (Gvar ty)) by (apply In_find_assoc; auto).
  destruct (globalenv_find_var p x ty ND F) as [b V].
  apply (Loopproof.global_var_types m p GEN x b ty V).
Qed.

Lemma LG :
  grel rb lfd ge geL
  /\ mrel rb (init_mem p) (init_mem (link p d))
  /\ ge_comp geL = ceL
  /\ (forall x, x <> dg_state_var d -> find_var ge x = None -> find_var geL x = None)
  /\ (has_states d = true ->
        find_var geL (dg_state_var d) = Some (dwb, Tstruct (dg_state_struct d))
     /\ get_block (init_mem (link p d)) dwb
        = Some (Tstruct (dg_state_struct d), zero_mval ceL (Tstruct (dg_state_struct d)))).
Proof. rewrite <- TY. apply link_globalenv; first [apply NDW | apply NDS | apply WFC | apply CV]. Qed.

Lemma GE_comp : ge_comp ge = ce.
Proof. rewrite globalenv_comp. apply TY. Qed.

(** How the glue's environment holds the controller's state, and how the
    linked program's memory holds it: in [Controller_DW], block [dwb]. *)
Definition crel (c : option mval) (mL : mem) : Prop :=
  (has_states d = true ->
     exists sv, get_block mL dwb = Some (Tstruct (dg_state_struct d), sv)
     /\ (exists sfs, sv = MVstruct sfs /\ map fst sfs = map st_name (dg_states d))
     /\ (forall s, c = Some s -> sv = s))
  /\ (forall s, c = Some s -> state_typed d s).

Lemma crel_extra: forall c mL mL', crel c mL -> same_extra rb mL mL' -> crel c mL'.
Proof.
  intros c mL mL' [C1 C2] X. split; auto. intros H. rewrite X by (apply dwb_extra; auto). auto.
Qed.

Lemma state_typed_shape:
  forall s, state_typed d s -> exists sfs, s = MVstruct sfs /\ map fst sfs = map st_name (dg_states d).
Proof. intros s (sfs & E & N & _). eauto. Qed.

(** The in/out globals. *)
Lemma gen_in_var: exists bu, find_var ge (nm_in_var m) = Some (bu, Tstruct (nm_in_struct m)).
Proof.
  destruct (generate_externals m p GEN) as (_ & _ & _ & _ & _ & _ & Fu & _).
  apply (globalenv_find_var p _ _ ND Fu).
Qed.

Lemma gen_out_var: exists by_, find_var ge (nm_out_var m) = Some (by_, Tstruct (nm_out_struct m)).
Proof.
  destruct (generate_externals m p GEN) as (_ & _ & _ & _ & _ & _ & _ & Fy).
  apply (globalenv_find_var p _ _ ND Fy).
Qed.

Lemma fields_names:
  forall ce ms fs, fields_have_type ce ms fs -> map fst fs = map fst ms.
Proof. induction 1; simpl; f_equal; auto. Qed.

Lemma load_path_root:
  forall mm b mv, load_path mm b [] = Some mv -> exists ty, get_block mm b = Some (ty, mv).
Proof.
  intros mm b mv H. unfold load_path in H. destruct (get_block mm b) as [[ty v]|]; [|discriminate].
  simpl in H. inversion H; subst. eauto.
Qed.

Section CONTROLLER.

Variables (arrivals : nat -> list arrival) (clock : nat -> Z) (tg : target).
Context {CSL : Type}.
Variable ctxL : ros_context CSL.

Local Notation ctx := (diagram_ctx m d arrivals clock tg).

Lemma ctrl_sim:
  forall ef targs tres vargs mm w vres t m' w' mL,
  is_ctrl ef = true -> in_ge ge (External ef targs tres) ->
  external_call ctx ge ef vargs mm w = Some (vres, t, m', w') ->
  mrel rb mm mL -> crel (w_ctrl w) mL ->
  exists mL', eval_funcall ctxL geL mL (wr w) (lfd (External ef targs tres)) (map (rv rb) vargs) (rtrace rb t)
                mL' (wr w') (rv rb vres)
     /\ mrel rb m' mL' /\ crel (w_ctrl w') mL' /\ w_subs w' = w_subs w.
Proof.
  intros ef targs tres vargs mm w vres t m' w' mL NC [x F] H R C.
  destruct (gen_fundef m p GEN x _ F) as [_ EX]. specialize (EX ef targs tres eq_refl).
  destruct LG as (G & _ & _ & _ & DW).
  destruct (dg_matches_spec m d MA) as (DIV & DIS & DOV & DOS & DI & DO).
  destruct ef; try discriminate NC; destruct EX as (-> & -> & -> & ->);
    destruct vargs; try discriminate H.
  - (* Controller_initialize *)
    cbn [external_call] in H. inversion H; subst. clear H.
    destruct (has_states d) eqn:HS.
    + destruct C as [C1 _]. destruct (C1 HS) as (sv & G0 & (sfs0 & -> & N0) & _).
      destruct (DW eq_refl) as [VDW _].
      destruct (init_call ctxL geL d mL (wr w) (MVstruct sfs0) dwb (fun _ => conj VDW (ex_intro _ _ G0))
                  (Tstruct (dg_state_struct d)) WF sfs0 HS G0 N0) as (m2 & E & G2 & O & NX).
      exists m2. split; [exact E|]. split; [|split; [|reflexivity]].
      * split; [rewrite NX; apply (mr_next _ _ _ R)|]. intros b. rewrite O; [apply (mr_get _ _ _ R)|].
        intros Eb. apply (dwb_extra d HS b). auto.
      * split.
        -- intros _. exists (dg_init d). split; auto. split; [apply state_typed_shape, dg_init_typed; auto|].
           intros s0 Es. simpl in Es. inversion Es; auto.
        -- intros s0 Es. simpl in Es. inversion Es; subst. apply dg_init_typed; auto.
    + exists mL. split; [|split; [exact R|split; [|reflexivity]]].
      * simpl. assert (E0: dg_states d = []) by (unfold has_states in HS; destruct (dg_states d); [auto|discriminate]).
        change (eval_funcall ctxL geL mL (wr w) (Internal (init_function d)) [] [] (free_vars mL []) (wr w) Vundef).
        eapply eval_funcall_internal with (out := Out_normal).
        -- reflexivity.
        -- unfold init_function. simpl. rewrite E0. simpl. apply exec_Sskip.
        -- reflexivity.
      * split; [intros E; congruence|]. intros s0 Es. simpl in Es. inversion Es; subst. apply dg_init_typed; auto.
  - (* Controller_step *)
    cbn [external_call] in H.
    destruct (w_ctrl w) as [s|] eqn:WC; [|discriminate].
    destruct gen_in_var as [bu VU]. destruct gen_out_var as [by_ VY].
    rewrite VU, VY in H.
    destruct (load_path mm bu []) as [uv|] eqn:LU; [|discriminate].
    destruct (load_path mm by_ []) as [yv0|] eqn:LY; [|discriminate].
    rewrite GE_comp in H.
    destruct (mval_typecheck ce (Tstruct (nm_in_struct m)) uv && mval_typecheck ce (Tstruct (nm_out_struct m)) yv0)
      eqn:TC; [|discriminate].
    apply andb_true_iff in TC as [TU TY0]. apply mval_typecheck_iff in TU. apply mval_typecheck_iff in TY0.
    destruct C as [C1 C2]. assert (ST: state_typed d s) by (apply C2; auto).
    assert (UT: inputs_typed d uv) by (apply (inputs_typed_of m W d uv DI TU)).
    destruct (dg_step_typed m d W WF MA s uv UT ST) as [S1 Y1].
    assert (GS: guard_step m d s uv = dg_step d s uv).
    { unfold guard_step. apply mval_typecheck_iff in Y1. rewrite Y1. reflexivity. }
    simpl ctx_step in H. rewrite GS in H.
    destruct (dg_step d s uv) as [s' yv] eqn:STEP. simpl in S1, Y1.
    replace (mval_typecheck ce (Tstruct (nm_out_struct m)) yv) with true in H by (symmetry; apply mval_typecheck_iff; auto).
    destruct (store_path mm by_ [] yv) as [m2|] eqn:SP; [|discriminate].
    inversion H; subst. clear H.
    destruct (load_path_root _ _ _ LU) as [tyU GU]. destruct (load_path_root _ _ _ LY) as [tyY GY].
    assert (NPu: rmv rb uv = uv) by (apply (rmv_no_ptr rb ce (composites_no_ptr m) uv _ TU); reflexivity).
    assert (NPy0: rmv rb yv0 = yv0) by (apply (rmv_no_ptr rb ce (composites_no_ptr m) yv0 _ TY0); reflexivity).
    assert (NPy: rmv rb yv = yv) by (apply (rmv_no_ptr rb ce (composites_no_ptr m) yv _ Y1); reflexivity).
    assert (GUL: get_block mL (rb bu) = Some (tyU, uv)) by (rewrite (mr_get _ _ _ R), GU; cbn [option_map]; unfold rblk; cbn [fst snd]; rewrite NPu; reflexivity).
    assert (GYL: get_block mL (rb by_) = Some (tyY, yv0)) by (rewrite (mr_get _ _ _ R), GY; cbn [option_map]; unfold rblk; cbn [fst snd]; rewrite NPy0; reflexivity).
    inversion TY0 as [ty0 v0 Hs0 Hv0 | id ms fsY SM FT | t0 n0 es0 L0 E0]; subst; [discriminate Hs0|].
    rewrite (out_members m W) in SM. inversion SM; subst ms.
    assert (NY: map fst fsY = map fst (dg_outputs d)).
    { rewrite (fields_names _ _ _ FT), DO. unfold ftype_members, prim_fields. rewrite !map_map. reflexivity. }
    destruct ST as (sfs & Es & Ns & Vs).
    assert (HSt: has_states d = true ->
                 find_var geL (dg_state_var d) = Some (dwb, Tstruct (dg_state_struct d))
                 /\ get_block mL dwb = Some (Tstruct (dg_state_struct d), s) /\ rb by_ <> dwb).
    { intros HS. destruct (DW HS) as [VDW _]. destruct (C1 HS) as (sv & G0 & _ & E0).
      rewrite (E0 s eq_refl) in G0. split; auto. split; auto. intros E. apply (dwb_extra d HS by_). auto. }
    assert (VUL: find_var geL (dg_in_var d) = Some (rb bu, Tstruct (dg_in_struct d)))
      by (rewrite DIV, DIS; apply (gr_var _ _ _ _ G _ _ _ VU)).
    assert (VYL: find_var geL (dg_out_var d) = Some (rb by_, Tstruct (dg_out_struct d)))
      by (rewrite DOV, DOS; apply (gr_var _ _ _ _ G _ _ _ VY)).
    destruct (step_call ctxL geL d mL (wr w) s uv (rb bu) dwb VUL (ex_intro _ tyU GUL) UT
                (fun HS => let H' := HSt HS in conj (proj1 H') (ex_intro _ _ (proj1 (proj2 H')))) Vs
                (rb by_) tyY (Tstruct (dg_state_struct d)) fsY sfs WF VYL GYL NY
                (fun HS => proj1 (proj2 (HSt HS))) Es Ns (fun HS => proj2 (proj2 (HSt HS))))
      as (m3 & E & GY3 & GS3 & O & NX).
    rewrite STEP in GY3, GS3. simpl in GY3, GS3.
    exists m3. split; [exact E|]. split; [|split; [|reflexivity]].
      * split; [rewrite NX, (store_path_next _ _ _ _ _ SP); apply (mr_next _ _ _ R)|].
        intros b. destruct (Pos.eq_dec b by_) as [->|Nb].
        -- rewrite GY3. destruct (get_block_store_same _ _ _ _ _ SP) as (ty' & mv & mv' & G1 & MS & G2).
           rewrite GY in G1. inversion G1; subst ty' mv. simpl in MS. inversion MS; subst mv'.
           rewrite G2. cbn [option_map]. unfold rblk. cbn [fst snd]. rewrite NPy. reflexivity.
        -- rewrite O.
           ++ rewrite (get_block_store_other _ _ _ _ _ _ SP Nb). apply (mr_get _ _ _ R).
           ++ intros Eb. apply Nb, (rbd_inj d); auto.
           ++ intros HS Eb. apply (dwb_extra d HS b). auto.
      * split.
        -- intros HS. exists s'. split; [apply GS3; auto|]. split; [apply state_typed_shape; auto|].
           intros s0 Es0. simpl in Es0. inversion Es0; auto.
        -- intros s0 Es0. simpl in Es0. inversion Es0; subst. auto.
Qed.

End CONTROLLER.

End NODE.

(** ** The theorem *)

Lemma state_types_ext:
  forall d ce, wf_composites ce ->
  (has_states d = true -> ~ In (dg_state_struct d) (composite_names ce)) ->
  forall ty, complete_type (composite_names ce) ty = true ->
     (forall mv, clamp (ce ++ state_types d) ty mv = clamp ce ty mv)
  /\ (forall mv, too_long (ce ++ state_types d) ty mv = too_long ce ty mv)
  /\ (forall dflt, default_mval dflt (ce ++ state_types d) ty = default_mval dflt ce ty).
Proof.
  intros d ce WFc Fr ty C. unfold state_types. destruct (has_states d) eqn:H.
  - specialize (Fr eq_refl). split; [|split]; intros.
    + apply clamp_extend; auto.
    + apply too_long_extend; auto.
    + apply default_mval_extend; auto.
  - rewrite app_nil_r. auto.
Qed.

Lemma rtrace_concat: forall rb l, rtrace rb (concat l) = concat (map (rtrace rb) l).
Proof. induction l as [|t l IH]; simpl; auto. rewrite rtrace_app, IH. reflexivity. Qed.

Definition linked_start_events (m : node_model) : trace :=
  map subscribe_event (subscribed m) ++ map advertise_event (published m).

Lemma rtrace_start: forall rb m, rtrace rb (start_events m) = linked_start_events m.
Proof.
  intros rb m. unfold start_events, linked_start_events. simpl. rewrite rtrace_app.
  f_equal; [induction (subscribed m) | induction (published m)]; simpl; auto; f_equal; auto.
Qed.

Lemma zero_state_shape:
  forall d ce, has_states d = true ->
  exists sfs, zero_mval (ce ++ state_types d) (Tstruct (dg_state_struct d)) = MVstruct sfs
           /\ map fst sfs = map st_name (dg_states d).
Proof.
  intros d ce H. unfold state_types. rewrite H. unfold zero_mval, default_mval. rewrite rev_app_distr. simpl.
  destruct (ident_eq (dg_state_struct d) (dg_state_struct d)) as [_|C]; [|congruence].
  eexists; split; [reflexivity|]. rewrite !map_map. reflexivity.
Qed.

Lemma rtrace_publish:
  forall rb m tps mvs, Forall2 (fun tp mv => mval_has_type (composites m) (Tstruct (tp_msg tp)) mv) tps mvs ->
  rtrace rb (publish_events m tps mvs) = publish_events m tps mvs.
Proof.
  intros rb m tps mvs H. unfold publish_events. induction H as [|tp mv tps mvs P H IH]; simpl; auto.
  rewrite IH. f_equal. f_equal. unfold sent. rewrite <- clamp_rmv. f_equal.
  apply (rmv_no_ptr rb (composites m) (composites_no_ptr m) _ (Tstruct (tp_msg tp))); auto.
Qed.

(** The linked node, with the generated [Controller_initialize] and
    [Controller_step] in place of the environment's controller and its
    state in [Controller_DW]: in every environment (any controller: the
    program no longer calls one), for every schedule of well-typed
    messages and every number [n] of cycles, the linked program
    terminates; its trace is the registrations of the topics followed by
    [n] cycles in each of which it publishes the related fields of the
    diagram's outputs, the diagram stepped once from the state its
    previous step left ([dg_init] first) on the related fields of the
    newest messages. *)
Definition linked_node_ok (m : node_model) (p : program) (d : diagram) : Prop :=
  forall arrivals clock tg n (CSL : Type) (ctxL : ros_context CSL),
  ctx_arrivals ctxL = arrivals -> ctx_time ctxL = clock -> ctx_target ctxL = tg ->
  arrivals_wt m (diagram_ctx m d arrivals clock tg) ->
     (exists t, program_behaves (link p d) ctxL n t)
  /\ (forall t, program_behaves (link p d) ctxL n t ->
      exists (s : nat -> mval) (evs : nat -> trace),
         s O = dg_init d
      /\ t = linked_start_events m ++ concat (map evs (seq 0 n))
      /\ forall i, (i < n)%nat ->
           exists u y mvs,
              evs i = publish_events m (published m) mvs ++ [Esleep (nm_period_ms m)]
           /\ input_values m (diagram_ctx m d arrivals clock tg) i u
           /\ dg_step d (s i) u = (s (S i), y)
           /\ Forall2 (published_value m y (clock (S i)) (newest_by m (diagram_ctx m d arrivals clock tg) i))
                      (published m) mvs).

(** The names of the state do not clash with the glue's. *)
Definition link_fresh (m : node_model) (d : diagram) : bool :=
  negb (in_ident (dg_state_var d) (global_names m))
  && (negb (has_states d) || negb (in_ident (dg_state_struct d) (composite_names (composites m)))).

Theorem linked_node_ddc:
  forall m p d, generate m = OK p -> dg_wf d = true -> dg_matches m d = true -> link_fresh m d = true ->
  linked_node_ok m p d.
Proof.
  intros m p d GEN WF MA LF arrivals clock tg n CSL ctxL ARR TIME TGT AWT.
  unfold link_fresh in LF. apply andb_true_iff in LF as [LF1 LF2].
  assert (FV: ~ In (dg_state_var d) (global_names m)).
  { intros I. apply in_ident_spec in I. rewrite I in LF1. discriminate. }
  assert (FS: has_states d = true -> ~ In (dg_state_struct d) (composite_names (composites m))).
  { intros H I. rewrite H in LF2. apply in_ident_spec in I. rewrite I in LF2. discriminate. }
  assert (W : wf_facts m) by (apply wf_facts_intro, (generate_sound m p GEN)).
  set (ctx := diagram_ctx m d arrivals clock tg).
  destruct (LG m p d GEN FV FS) as (G & R0 & CL & _ & DW).
  assert (CE := GE_comp m p GEN).
  assert (WFc := Gluefacts.gen_wf_composites m p GEN).
  assert (EXT := state_types_ext d (composites m) WFc FS).
  assert (MSG: forall tp, In tp (nm_topics m) -> msg_ok (globalenv p) (globalenv (link p d)) (tp_msg tp)).
  { intros tp Htp mv. rewrite CL, CE.
    assert (C: complete_type (composite_names (composites m)) (Tstruct (tp_msg tp)) = true).
    { apply Loopproof.complete_struct. left. apply (Gluefacts.gen_msg_in m p GEN tp Htp). }
    destruct (EXT _ C) as (E1 & E2 & _). split; auto. }
  (* the run of the glue *)
  destruct (diagram_node_ddc m p d GEN WF MA arrivals clock tg n AWT) as [[t0 B0] RUN].
  destruct B0 as [fd mm' w' v FM EV].
  destruct (@sim (rbd d) (rbd_inj d) (rbd_succ d) (link_fundef d) mval CSL ctx ctxL
                (globalenv p) (globalenv (link p d)) G ARR TIME TGT) with (crel := crel d) as (_ & SF & _).
  - intros topic msgty q targs tres [x F] cb. destruct (gen_fundef m p GEN x _ F) as [_ EX].
    destruct (EX _ _ _ eq_refl) as (tp & Htp & -> & ->). split.
    + apply MSG. apply in_subscribed in Htp; tauto.
    + intros k a Ha Ht. simpl in Ht.
      apply (rmv_no_ptr (rbd d) (composites m) (composites_no_ptr m) _ (Tstruct (tp_msg tp))); [|reflexivity].
      apply (AWT k a tp Ha Htp). auto.
  - intros topic msgty targs tres [x F]. destruct (gen_fundef m p GEN x _ F) as [_ EX].
    destruct (EX _ _ _ eq_refl) as (tp & Htp & ->). apply MSG; auto.
  - intros f [x F] y ty I. destruct (gen_fundef m p GEN x _ F) as [IN _].
    destruct (IN f eq_refl y ty I) as (tp & Htp & ->). rewrite CL, CE.
    assert (C: complete_type (composite_names (composites m)) (Tstruct (tp_msg tp)) = true).
    { apply Loopproof.complete_struct. left. apply (Gluefacts.gen_msg_in m p GEN tp). apply in_published in Htp; tauto. }
    destruct (EXT _ C) as (_ & _ & E3). apply E3.
  - reflexivity.
  - intros ef targs tres NC. destruct ef; try discriminate NC; reflexivity.
  - intros fd0 [x F]. destruct fd0 as [f|ef targs tres]; [reflexivity|].
    destruct (gen_fundef m p GEN x _ F) as [_ EX]. specialize (EX ef targs tres eq_refl).
    destruct ef; try reflexivity; destruct EX as (_ & _ & -> & ->); reflexivity.
  - apply (crel_extra d).
  - intros. eapply ctrl_sim; eauto.
  - (* the linked run *)
    assert (INF: in_ge (globalenv p) fd) by (exists (prog_main p); exact FM).
    assert (C0: crel d (w_ctrl (initial_world ctx n)) (init_mem (link p d))).
    { split; [|intros s0 E; discriminate]. intros H. destruct (DW H) as [_ G0].
      destruct (zero_state_shape d (composites m) H) as (sfs & Z & N).
      exists (zero_mval (composites m ++ state_types d) (Tstruct (dg_state_struct d))).
      split; auto. split; [eauto|]. intros s0 E; discriminate. }
    assert (S0: subs_ok (rbd d) ctx (globalenv p) (globalenv (link p d)) (initial_world ctx n))
      by (intros s0 []).
    destruct (SF _ _ _ _ _ _ _ _ EV INF _ R0 C0 S0) as (mL' & EL & _).
    assert (BL: program_behaves (link p d) ctxL n (rtrace (rbd d) t0)).
    { econstructor.
      - simpl. apply (gr_funct _ _ _ _ G _ _ FM).
      - replace (initial_world ctxL n) with (wr (CSL := CSL) (initial_world ctx n))
          by (unfold initial_world, wr; simpl; rewrite TIME; reflexivity).
        exact EL. }
    split; [eauto|].
    intros t B. rewrite (program_behaves_determ _ _ _ _ _ _ B BL).
    destruct (RUN t0 (program_runs _ _ _ _ _ _ _ _ FM EV)) as (s & evs & Es & Et & Ec).
    exists s, (fun i => rtrace (rbd d) (evs i)). split; [exact Es|]. split.
    + rewrite Et, rtrace_app, rtrace_start, rtrace_concat, map_map. reflexivity.
    + intros i Hi. destruct (Ec i Hi) as (u & y & mvs & Ei & IV & ST & PV).
      exists u, y, mvs. split; [|split; [exact IV|split; [exact ST|exact PV]]].
      rewrite Ei. simpl. rewrite rtrace_app. f_equal.
      apply rtrace_publish. clear -PV. induction PV as [|tp mv tps mvs P PV IH]; constructor; auto. apply (proj1 P).
Qed.
