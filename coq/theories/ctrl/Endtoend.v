(** * The whole node, its controller a block diagram *)

(** T2 ([Loopproof.generate_node_ddc]) holds in every environment, with
    any controller that reads the inputs global and writes only the
    outputs global and its own state.  [Diagramproof.step_call] proves
    that the C generated from a diagram is such a controller, computing
    [Diagram.dg_step].  This file puts the two together:
    [diagram_node_ddc] is T2 in the environments whose controller *is*
    the diagram ([diagram_ctx]): for every message arrival schedule (with its clock) and
    number [n] of cycles, the node runs to completion, and in each cycle
    the diagram steps once, from its state threaded from [dg_init], on
    the inputs that [DDC.input_values] prescribes (the related fields of
    the newest messages), and the published messages carry the related
    fields of the diagram's outputs.

    How the two proofs meet: the glue's semantics treats
    [Controller_step] as the external function of the environment model
    ([Environment.external_call]): it reads the whole inputs global and
    writes only the outputs global and the controller's own state, and
    nothing else of the program touches that state.  The controller's
    theorem ([Main.controller_step_correct]) shows that the generated
    [Controller_step] behaves exactly so: its only effects are the new
    outputs in [Controller_Y] and the new state in [Controller_DW], both
    computed by [dg_step] from [Controller_U] and [Controller_DW]; it emits
    no event.  [Link.linked_node_ddc] (T8) then states the same for the
    linked program, glue and generated controller in one semantics, the
    state in memory rather than in the environment. *)

From Coq Require Import String List ZArith Bool Lia.
From ROSGen Require Import Errors Syntax Values Memory Environment Semantics
                           NodeModel Wellformed Generator Generatorspec Generatorproof DDC Loopproof
                           Diagram Diagramgen Diagramproof.
Import ListNotations.

(** ** The diagram implements the node's controller interface *)

Fixpoint fields_eqb (a b : list (ident * prim)) : bool :=
  match a, b with
  | [], [] => true
  | (x, p) :: a', (y, q) :: b' => String.eqb x y && prim_eqb p q && fields_eqb a' b'
  | _, _ => false
  end.

Lemma fields_eqb_true: forall a b, fields_eqb a b = true -> a = b.
Proof.
  induction a as [|[x p] a IH]; destruct b as [|[y q] b]; simpl; intros H; try discriminate; auto.
  apply andb_true_iff in H as [H H3]. apply andb_true_iff in H as [H1 H2].
  apply String.eqb_eq in H1. apply prim_eqb_true in H2. subst. f_equal. auto.
Qed.

(** The scalar fields of a controller, if all its fields are scalars
    (a diagram has no array inputs or outputs). *)
Fixpoint prims_of (fs : list (ident * ftype)) : option (list (ident * prim)) :=
  match fs with
  | [] => Some []
  | (x, FTprim q) :: fs' => match prims_of fs' with Some l => Some ((x, q) :: l) | None => None end
  | _ :: _ => None
  end.

Lemma prims_of_spec: forall fs l, prims_of fs = Some l -> fs = prim_fields l.
Proof.
  induction fs as [|[x [q| |]] fs IH]; simpl; intros l H; try discriminate.
  - inversion H; reflexivity.
  - destruct (prims_of fs) as [l'|] eqn:E; [|discriminate]. inversion H; subst.
    simpl. f_equal. auto.
Qed.

Definition fields_match (a : list (ident * prim)) (b : list (ident * ftype)) : bool :=
  match prims_of b with Some l => fields_eqb a l | None => false end.

Lemma fields_match_spec: forall a b, fields_match a b = true -> b = prim_fields a.
Proof.
  unfold fields_match; intros a b H. destruct (prims_of b) as [l|] eqn:E; [|discriminate].
  apply fields_eqb_true in H. subst. apply prims_of_spec; auto.
Qed.

Definition dg_matches (m : node_model) (d : diagram) : bool :=
  String.eqb (dg_in_var d) (nm_in_var m) && String.eqb (dg_in_struct d) (nm_in_struct m)
  && String.eqb (dg_out_var d) (nm_out_var m) && String.eqb (dg_out_struct d) (nm_out_struct m)
  && fields_match (dg_inputs d) (nm_inputs m) && fields_match (dg_outputs d) (nm_outputs m).

Lemma dg_matches_spec:
  forall m d, dg_matches m d = true ->
  dg_in_var d = nm_in_var m /\ dg_in_struct d = nm_in_struct m
  /\ dg_out_var d = nm_out_var m /\ dg_out_struct d = nm_out_struct m
  /\ nm_inputs m = prim_fields (dg_inputs d) /\ nm_outputs m = prim_fields (dg_outputs d).
Proof.
  intros m d H. unfold dg_matches in H.
  repeat match goal with H : (_ && _) = true |- _ => apply andb_true_iff in H as [? ?] end.
  repeat match goal with H : String.eqb _ _ = true |- _ => apply String.eqb_eq in H end.
  repeat match goal with H : fields_match _ _ = true |- _ => apply fields_match_spec in H end.
  tauto.
Qed.

(** ** Steps on values of their types give values of their types *)

Section TYPED.

Variable d : diagram.
Variables (s u : mval).

Definition inputs_typed : Prop :=
  forall f q, find_assoc f (dg_inputs d) = Some q ->
  exists v, mval_get u [Sfield f] = Some (MVscalar v) /\ typed v q.

(** A state: one member per state, in order, each of its type. *)
Definition state_typed (x : mval) : Prop :=
  exists sfs, x = MVstruct sfs /\ map fst sfs = map st_name (dg_states d)
  /\ forall st, In st (dg_states d) ->
       exists v, mval_get x [Sfield (st_name st)] = Some (MVscalar v) /\ typed v (st_type st).

Hypothesis UT : inputs_typed.
Hypothesis ST : state_typed s.

Definition env_typed (tctx : list (ident * prim)) (env : senv) : Prop :=
  forall x q, find_assoc x tctx = Some q -> typed (sig env x) q.

Lemma sig_typed:
  forall tctx env x q, env_typed tctx env -> has_type tctx x q = true -> typed (sig env x) q.
Proof. intros tctx env x q E H. apply E. apply has_type_spec; auto. Qed.

Lemma eval_block_typed:
  forall tctx env b q, env_typed tctx env -> block_ok d (sig_type tctx) b q = true ->
  typed (eval_block s u env b q) q.
Proof.
  intros tctx env b q E OK. unfold block_ok in OK. apply andb_true_iff in OK as [SQ OK].
  destruct b as [f|f|c|k a|terms|a b|a b|a|ismax args|lo hi a|op qa a b|op args|crit qc thr a c b];
    simpl.
  - destruct (find_assoc f (dg_inputs d)) as [q'|] eqn:F; [|discriminate].
    apply prim_eqb_true in OK; subst q'. destruct (UT f q F) as [v [M T]].
    unfold field_val; rewrite M; exact T.
  - destruct (state_type d f) as [q'|] eqn:F; [|discriminate].
    apply prim_eqb_true in OK; subst q'.
    destruct (state_type_In d f q F) as [st [I [<- <-]]].
    destruct ST as [sfs [_ [_ V]]]. destruct (V st I) as [v [M T]].
    unfold field_val; rewrite M; exact T.
  - apply val_of_prim_typed; auto.
  - apply andb_true_iff in OK as [OK Fa]. apply andb_true_iff in OK as [N Kt].
    apply arith_typed; auto. eapply sig_typed; eauto. apply val_of_prim_typed; auto.
    left; discriminate.
  - apply andb_true_iff in OK as [OK F]. apply andb_true_iff in OK as [N L].
    destruct terms as [|[p a] terms]; [discriminate|]. simpl in F.
    apply andb_true_iff in F as [Fa F].
    assert (T0: typed (if p then sig env a else negate q (sig env a)) q).
    { destruct p; [eapply sig_typed; eauto | apply negate_typed; auto; eapply sig_typed; eauto]. }
    revert T0. generalize (if p then sig env a else negate q (sig env a)).
    induction terms as [|[p' b] terms IH]; intros v0 T0; simpl; auto.
    simpl in F. apply andb_true_iff in F as [Fb F]. apply IH; auto.
    apply arith_typed; auto. eapply sig_typed; eauto. destruct p'; left; discriminate.
  - apply andb_true_iff in OK as [OK Fb]. apply andb_true_iff in OK as [N Fa].
    apply arith_typed; auto; [eapply sig_typed; eauto | eapply sig_typed; eauto | left; discriminate].
  - apply andb_true_iff in OK as [OK Fb]. apply andb_true_iff in OK as [Fl Fa].
    assert (N: num_prim q = true) by (destruct q; simpl in Fl; try discriminate; reflexivity).
    apply arith_typed; auto; eapply sig_typed; eauto.
  - apply andb_true_iff in OK as [Fl Fa]. assert (T := sig_typed _ _ _ _ E Fa).
    destruct q; simpl in Fl; try discriminate; destruct (sig env a); simpl in T; try contradiction; exact I.
  - apply andb_true_iff in OK as [OK F]. apply andb_true_iff in OK as [N L].
    destruct args as [|a args]; [discriminate|]. simpl in F.
    apply andb_true_iff in F as [Fa F].
    assert (T0 := sig_typed _ _ _ _ E Fa). revert T0. generalize (sig env a).
    induction args as [|b args IH]; intros v0 T0; simpl; auto.
    simpl in F. apply andb_true_iff in F as [Fb F]. apply IH; auto.
    destruct (compare _ q (sig env b) v0); auto. eapply sig_typed; eauto.
  - apply andb_true_iff in OK as [OK Fa]. apply andb_true_iff in OK as [OK Th].
    apply andb_true_iff in OK as [N Tl]. unfold saturate.
    destruct (compare Rgt q _ hi); [apply val_of_prim_typed; auto|].
    destruct (compare Rlt q _ lo); [apply val_of_prim_typed; auto|]. eapply sig_typed; eauto.
  - apply andb_true_iff in OK as [OK _]. apply andb_true_iff in OK as [OK _].
    apply andb_true_iff in OK as [B _]. apply prim_eqb_true in B; subst. apply of_bool_typed.
  - apply andb_true_iff in OK as [OK _]. apply andb_true_iff in OK as [B _].
    apply prim_eqb_true in B; subst. apply of_bool_typed.
  - apply andb_true_iff in OK as [OK _]. apply andb_true_iff in OK as [OK _].
    apply andb_true_iff in OK as [Fa Fb].
    destruct (match crit with Cge => _ | Cgt => _ | Cne0 => _ end); eapply sig_typed; eauto.
Qed.

End TYPED.

Lemma eval_eqs_typed:
  forall d s u, inputs_typed d u -> state_typed d s ->
  forall eqs tctx env tctx', eqs_ok d tctx eqs = Some tctx' -> env_typed tctx env ->
  env_typed tctx' (eval_eqs s u env eqs).
Proof.
  intros d s u UT ST. induction eqs as [|[x q b] eqs IH]; intros tctx env tctx' OK E; simpl in OK |- *.
  - inversion OK; subst; auto.
  - destruct (block_ok d (sig_type tctx) b q && negb (in_ident x (map fst tctx))) eqn:B; [|discriminate].
    apply andb_true_iff in B as [B _].
    apply (IH _ _ _ OK). intros y qy F. simpl in F. unfold sig; simpl.
    destruct (string_dec y x) as [->|N].
    + inversion F; subst. eapply eval_block_typed; eauto.
    + apply E; auto.
Qed.

(** ** The controller structs of the glue *)

Section STRUCTS.

Variable m : node_model.
Hypothesis W : wf_facts m.

Definition members_of (fs : list (ident * prim)) : list (ident * type) :=
  map (fun fq => (fst fq, ctype_of_prim (snd fq))) fs.

Definition ftype_members (fs : list (ident * ftype)) : list (ident * type) :=
  map (fun xt => (fst xt, ctype_of_ftype (snd xt))) fs.

Lemma ftype_members_prim: forall l, ftype_members (prim_fields l) = members_of l.
Proof. intros l. unfold ftype_members, prim_fields. rewrite map_map. reflexivity. Qed.

Lemma find_assoc_members:
  forall x fs q, find_assoc x fs = Some q -> find_assoc x (members_of fs) = Some (ctype_of_prim q).
Proof.
  induction fs as [|[y r] fs IH]; simpl; intros q H; [discriminate|].
  destruct (string_dec x y); [congruence|auto].
Qed.

Lemma in_members: struct_members (composites m) (nm_in_struct m) = Some (ftype_members (nm_inputs m)).
Proof.
  unfold struct_members, composites. rewrite find_composite_skip_msgs by (apply in_struct_not_msg; auto).
  unfold find_composite; simpl. destruct (string_dec (nm_in_struct m) (nm_in_struct m)); [reflexivity | congruence].
Qed.

Lemma out_members: struct_members (composites m) (nm_out_struct m) = Some (ftype_members (nm_outputs m)).
Proof.
  unfold struct_members, composites. rewrite find_composite_skip_msgs by (apply out_struct_not_msg; auto).
  unfold find_composite; simpl.
  destruct (string_dec (nm_in_struct m) (nm_out_struct m)) as [E|_]; [elim (in_out_structs_differ m W); auto|].
  destruct (string_dec (nm_out_struct m) (nm_out_struct m)); [reflexivity | congruence].
Qed.

(** A struct of the given scalars, each of its field's type. *)
Lemma fields_typed_of:
  forall (fs : list (ident * prim)) (val_of : ident * prim -> val),
  (forall fq, In fq fs -> typed (val_of fq) (snd fq)) ->
  fields_have_type (composites m) (members_of fs) (map (fun fq => (fst fq, MVscalar (val_of fq))) fs).
Proof.
  induction fs as [|fq fs IH]; intros val_of T; simpl; constructor.
  - constructor; [destruct (snd fq); reflexivity | apply T; simpl; auto].
  - apply IH. intros; apply T; simpl; auto.
Qed.

(** Inputs of the inputs' struct type have typed fields. *)
Lemma inputs_typed_of:
  forall d u, nm_inputs m = prim_fields (dg_inputs d) ->
  mval_has_type (composites m) (Tstruct (nm_in_struct m)) u -> inputs_typed d u.
Proof.
  intros d u DI H f q F.
  inversion H as [ty0 v0 Sc0 Hv0 | id members fs SM FT | t0 n0 es0 L0 E0]; subst;
    [simpl in Sc0; discriminate|].
  rewrite in_members, DI, ftype_members_prim in SM. inversion SM; subst members.
  assert (FM: find_assoc f (members_of (dg_inputs d)) = Some (ctype_of_prim q))
    by (apply find_assoc_members; auto).
  clear SM H DI F.
  revert FT FM. generalize (members_of (dg_inputs d)) as ms. intros ms FT FM.
  induction FT as [|g t mv ms' fs' Hmv Hfs IH]; simpl in FM |- *; [discriminate|].
  destruct (string_dec f g).
  - inversion FM; subst t.
    inversion Hmv as [ty v Sc Hv | id' members' fs'' SM' FT' | t' n' es' L' E']; subst;
      [| destruct q; discriminate | destruct q; discriminate].
    exists v. split; auto.
  - auto.
Qed.

End STRUCTS.

(** ** The environments whose controller is the diagram *)

Section NODE.

Variable m : node_model.
Variable d : diagram.

(** The outputs of a step, or zeros for outputs of another type (which a
    well-formed diagram never gives on inputs and state of their types:
    [guard_step_eq]). *)
Definition zero_outputs : mval :=
  MVstruct (map (fun fq => (fst fq, MVscalar (zero_of_prim (snd fq)))) (dg_outputs d)).

Definition guard_step (s u : mval) : mval * mval :=
  let r := dg_step d s u in
  if mval_typecheck (composites m) (Tstruct (nm_out_struct m)) (snd r) then r
  else (fst r, zero_outputs).

Definition diagram_ctx (arrivals : nat -> list arrival) (clock : nat -> Z) (tg : target) : ros_context mval :=
  mkctx arrivals clock (dg_init d) guard_step tg.

Hypothesis W : wf_facts m.
Hypothesis WF : dg_wf d = true.
Hypothesis MA : dg_matches m d = true.

Lemma zero_outputs_typed: mval_has_type (composites m) (Tstruct (nm_out_struct m)) zero_outputs.
Proof.
  destruct (dg_matches_spec m d MA) as (_ & _ & _ & _ & _ & DO).
  econstructor; [rewrite (out_members m W), DO, ftype_members_prim; reflexivity|]. apply fields_typed_of.
  intros [f q] _. simpl. destruct q; reflexivity.
Qed.

Lemma diagram_controller_wt: forall arrivals clock tg, controller_wt m (diagram_ctx arrivals clock tg).
Proof.
  intros arrivals clock tg s u. simpl. unfold guard_step.
  destruct (mval_typecheck _ _ (snd (dg_step d s u))) eqn:T.
  - apply mval_typecheck_iff; auto.
  - apply zero_outputs_typed.
Qed.

(** On inputs and a state of their types, the diagram's step gives a
    state and outputs of their types, and the guard lets it through. *)
Lemma dg_step_typed:
  forall s u, inputs_typed d u -> state_typed d s ->
  state_typed d (fst (dg_step d s u))
  /\ mval_has_type (composites m) (Tstruct (nm_out_struct m)) (snd (dg_step d s u)).
Proof.
  intros s u UT ST.
  destruct (dg_wf_inv d WF) as [tctx [EQ [FS [OO [NDS NDO]]]]].
  destruct (dg_matches_spec m d MA) as (_ & _ & _ & _ & _ & DO).
  assert (E := eval_eqs_typed d s u UT ST (dg_eqs d) [] [] tctx EQ (fun x q F => ltac:(discriminate))).
  set (env := eval_eqs s u [] (dg_eqs d)) in E.
  unfold dg_step, step_signals. fold env. simpl. split.
  - exists (map (fun st => (st_name st, MVscalar (next_state s env st))) (dg_states d)).
    split; [reflexivity|]. split; [rewrite map_map; reflexivity|].
    intros st I. exists (next_state s env st). split.
    + simpl. erewrite In_find_assoc; [reflexivity | |].
      * rewrite map_map; simpl; auto.
      * apply in_map_iff. eauto.
    + rewrite forallb_forall in FS. specialize (FS st I). unfold state_ok in FS.
      apply andb_true_iff in FS as [FS K]. apply andb_true_iff in FS as [FS Fi].
      unfold next_state. destruct (st_kind st) as [|kt [[lo hi]|]].
      * eapply sig_typed; eauto.
      * apply andb_true_iff in K as [K L]. apply andb_true_iff in K as [Fl Tk].
        apply andb_true_iff in L as [Tl Th].
        assert (N: num_prim (st_type st) = true) by (destruct (st_type st); simpl in Fl; try discriminate; reflexivity).
        assert (Tx: typed (field_val s (st_name st)) (st_type st)).
        { destruct ST as [sfs [_ [_ V]]]. destruct (V st I) as [v [M T]]. unfold field_val; rewrite M; auto. }
        unfold saturate.
        destruct (compare Rgt _ _ hi); [apply val_of_prim_typed; auto|].
        destruct (compare Rlt _ _ lo); [apply val_of_prim_typed; auto|].
        apply arith_typed; auto; try (left; discriminate).
        apply arith_typed; auto; try (left; discriminate).
        -- apply val_of_prim_typed; auto.
        -- eapply sig_typed; eauto.
      * apply andb_true_iff in K as [K _]. apply andb_true_iff in K as [Fl Tk].
        assert (N: num_prim (st_type st) = true) by (destruct (st_type st); simpl in Fl; try discriminate; reflexivity).
        assert (Tx: typed (field_val s (st_name st)) (st_type st)).
        { destruct ST as [sfs [_ [_ V]]]. destruct (V st I) as [v [M T]]. unfold field_val; rewrite M; auto. }
        apply arith_typed; auto; try (left; discriminate).
        apply arith_typed; auto; try (left; discriminate).
        -- apply val_of_prim_typed; auto.
        -- eapply sig_typed; eauto.
  - unfold output_value. econstructor; [rewrite (out_members m W), DO, ftype_members_prim; reflexivity|].
    apply (fields_typed_of m (dg_outputs d)
             (fun fq => match find_assoc (fst fq) (dg_outs d) with Some x => sig env x | None => Vundef end)).
    intros fq I. unfold outs_ok in OO.
    apply andb_true_iff in OO as [_ OO]. rewrite forallb_forall in OO. specialize (OO fq I).
    destruct (find_assoc (fst fq) (dg_outs d)) as [x|]; [eapply sig_typed; eauto | discriminate].
Qed.

End NODE.

(** ** The theorem *)

Lemma dg_init_typed: forall d, dg_wf d = true -> state_typed d (dg_init d).
Proof.
  intros d WF. destruct (dg_wf_inv d WF) as [tctx [EQ [FS [OO [NDS NDO]]]]].
  exists (map (fun st => (st_name st, MVscalar (st_init st))) (dg_states d)).
  split; [reflexivity|]. split; [rewrite map_map; reflexivity|].
  intros st I. exists (st_init st). split.
  - simpl. erewrite In_find_assoc; [reflexivity | |].
    + rewrite map_map; simpl; auto.
    + apply in_map_iff. eauto.
  - rewrite forallb_forall in FS. specialize (FS st I). unfold state_ok in FS.
    repeat (apply andb_true_iff in FS as [FS ?]). apply val_of_prim_typed; auto.
Qed.

(** T2 with the diagram as the controller: for every node model [m] and
    diagram [d] that [generate] and [dg_wf] accept and whose interface
    is the controller's of [m], for every arrival schedule whose messages
    are well typed and every number [n] of cycles: the node terminates,
    and its trace is the node's start followed by [n] cycles in each of
    which the diagram steps once, from the state its previous step left
    (from [dg_init] in the first), on the inputs [DDC.input_values]
    prescribes, and the published messages carry its outputs
    ([DDC.published_value]). *)
Definition diagram_node_ok (m : node_model) (p : program) (d : diagram) : Prop :=
  forall arrivals clock tg n, arrivals_wt m (diagram_ctx m d arrivals clock tg) ->
     (exists t, program_behaves p (diagram_ctx m d arrivals clock tg) n t)
  /\ (forall t, program_behaves p (diagram_ctx m d arrivals clock tg) n t ->
      exists (s : nat -> mval) (evs : nat -> trace),
         s O = dg_init d
      /\ t = start_events m ++ concat (map evs (seq 0 n))
      /\ forall i, (i < n)%nat ->
           exists u y mvs,
              evs i = Estep u y :: publish_events m (published m) mvs ++ [Esleep (nm_period_ms m)]
           /\ input_values m (diagram_ctx m d arrivals clock tg) i u
           /\ dg_step d (s i) u = (s (S i), y)
           /\ Forall2 (published_value m y (clock (S i)) (newest_by m (diagram_ctx m d arrivals clock tg) i)) (published m) mvs).

Theorem diagram_node_ddc:
  forall m p d, generate m = OK p -> dg_wf d = true -> dg_matches m d = true ->
  diagram_node_ok m p d.
Proof.
  intros m p d GEN WF MA arrivals clock tg n AWT.
  assert (W: wf_facts m) by (apply wf_facts_intro, (Generatorproof.generate_sound m p GEN)).
  destruct (dg_matches_spec m d MA) as (_ & _ & _ & _ & DI & _).
  destruct (generate_node_ddc m p GEN mval (diagram_ctx m d arrivals clock tg) n AWT
              (diagram_controller_wt m d W MA arrivals clock tg)) as [EX RUN].
  split; [exact EX|]. intros t B.
  destruct (RUN t B) as [s [evs [S0 [T C]]]].
  exists s, evs. split; [exact S0|]. split; [exact T|].
  (* the states are of their types all along, so the guard never acts *)
  assert (ST: forall i, (i <= n)%nat -> state_typed d (s i)).
  { induction i as [|i IH]; intros Hi.
    - rewrite S0. apply dg_init_typed; auto.
    - destruct (C i ltac:(lia)) as [u [y [mvs [_ [[UT _] [STEP _]]]]]].
      simpl in STEP. unfold guard_step in STEP.
      assert (UT' := inputs_typed_of m W d u DI UT).
      destruct (dg_step_typed m d W WF MA (s i) u UT' (IH ltac:(lia))) as [S1 Y1].
      apply mval_typecheck_iff in Y1. rewrite Y1 in STEP.
      rewrite STEP in S1. exact S1. }
  intros i Hi. destruct (C i Hi) as [u [y [mvs [E [IV [STEP P]]]]]].
  exists u, y, mvs. split; [exact E|]. split; [exact IV|]. split; [|exact P].
  simpl in STEP. unfold guard_step in STEP.
  assert (UT' := inputs_typed_of m W d u DI (proj1 IV)).
  destruct (dg_step_typed m d W WF MA (s i) u UT' (ST i ltac:(lia))) as [_ Y1].
  apply mval_typecheck_iff in Y1. rewrite Y1 in STEP. exact STEP.
Qed.
