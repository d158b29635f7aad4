(** * Correctness proof for the generated node (theorem T2) *)

(** For every well-formed node model [m] and its program [p], [node_ddc m p]
    holds: in every environment with well-typed messages and controller,
    [main] terminates after [n] cycles and its trace is a run of [n]
    correct cycles ([DDC.run_ok]).

    The proof follows [main]: initialisation of the controller
    ([Einit]: from then on the world holds the controller state
    [Some s]), registration of the subscriptions and advertisements (one
    [Esubscribe] / [Eadvertise] event each, [start_events]), then the
    loop, with the invariant [loop_inv]: after
    [k] cycles, the global of every subscribed topic agrees, on the
    paths that the node reads ([reads_agree], [read_paths]), with the
    newest message received in those cycles (zero if none), every local
    [c_cmd] holds an object of its type, and the world has the model's
    subscriptions, [k] spins, and [n - k] answers of [ros_ok] left.
    Each cycle uses T1 ([Glueproof]) for the callbacks run by
    [ros_spinOnce], for [input_glue] and for the output glue.  The facts
    that do not depend on the program (queues, sequences, runs from
    cycles) are in [Loopfacts], which this file exports. *)

From Coq Require Import String List ZArith Bool Lia.
From ROSGen Require Import Errors Maps Syntax Values Memory Environment Semantics NodeModel Wellformed Generator Generatorspec Stampspec Generatorproof Assignproof.
From ROSGen Require Import DDC Copyproof Glueproof.
From ROSGen Require Export Loopfacts.
Import ListNotations.

Local Open Scope list_scope.

Section NODE.

Variable m : node_model.
Variable p : program.
Hypothesis GEN : generate m = OK p.

Context {CS : Type}.
Variable ctx : ros_context CS.
Hypothesis AWT : arrivals_wt m ctx.
Hypothesis CWT : controller_wt m ctx.

Let W : wf_facts m := wf_facts_intro m (generate_sound m p GEN).
Let ND : NoDup (map fst (prog_defs p)) := generate_names_distinct m p GEN.

Local Notation ge := (globalenv p).
Local Notation ce := (composites m).

Definition subs_of : list subscription := map sub_of (subscribed m).
Definition advs_of : list string := map tp_name (published m).

(** The world after [k] cycles, with [r] answers of [ros_ok] left and
    controller state [s]. *)
Definition wld (k r : nat) (s : CS) : world CS := mkworld subs_of advs_of k r (Some s) (ctx_time ctx k).

(** *** Facts on the program *)

Lemma types_eq: prog_types p = ce.
Proof. apply (gen_types m p GEN). Qed.

Lemma fun_not_var: forall x fd, find_def p x = Some (Gfun fd) -> find_var ge x = None.
Proof.
  intros x fd F. destruct (find_var ge x) as [[b ty]|] eqn:V; auto.
  apply find_var_globalenv in V; auto. congruence.
Qed.

Lemma def_name: forall x d, find_def p x = Some d -> In x (map fst (prog_defs p)).
Proof.
  intros x d F. unfold find_def in F. apply Semantics.find_assoc_In in F.
  apply (in_map fst _ _ F).
Qed.

Lemma global_var_block:
  forall mm x b ty, globals_typed p mm -> find_var ge x = Some (b, ty) -> get_block mm b <> None.
Proof. intros mm x b ty GT V. destruct (GT _ _ _ V) as (v & G & _). congruence. Qed.

Lemma find_var_same_block:
  forall x y bx tx ty, find_var ge x = Some (bx, tx) -> find_var ge y = Some (bx, ty) -> x = y /\ tx = ty.
Proof.
  intros x y bx tx ty Vx Vy. destruct (string_dec x y) as [->|N].
  - rewrite Vx in Vy; inversion Vy; auto.
  - exfalso. eapply (globalenv_vars_disjoint p x y bx tx bx ty); eauto.
Qed.

Lemma global_names_nodup: NoDup (global_names m).
Proof. apply wf_globals_nodup; auto. Qed.

Lemma msg_var_inj:
  forall tp1 tp2, In tp1 (subscribed m) -> In tp2 (subscribed m) ->
  msg_var (tp_cname tp1) = msg_var (tp_cname tp2) -> tp1 = tp2.
Proof.
  intros tp1 tp2 H1 H2 E.
  generalize global_names_nodup; unfold global_names; intros N.
  do 4 apply NoDup_app_right in N. apply NoDup_app_left in N.
  apply (NoDup_map_inj_in _ _ _ _ _ _ N H1 H2 E).
Qed.

Lemma callback_inj:
  forall tp1 tp2, In tp1 (subscribed m) -> In tp2 (subscribed m) ->
  callback_name (tp_cname tp1) = callback_name (tp_cname tp2) -> tp1 = tp2.
Proof.
  intros tp1 tp2 H1 H2 E.
  generalize global_names_nodup; unfold global_names; intros N.
  do 6 apply NoDup_app_right in N. apply NoDup_app_left in N.
  apply (NoDup_map_inj_in _ _ _ _ _ _ N H1 H2 E).
Qed.

(** The clock globals of the timed topics (rule 4.12): distinct from each
    other, from the topics' messages and from the controller's globals. *)
Lemma msgs_clocks_nodup:
  NoDup (map (fun tp => msg_var (tp_cname tp)) (subscribed m) ++ flat_map clock_names (timed m)).
Proof.
  generalize global_names_nodup; unfold global_names; intros N.
  do 4 apply NoDup_app_right in N. rewrite app_assoc in N. apply NoDup_app_left in N. exact N.
Qed.

Lemma clock_name_topic:
  forall tp1 tp2 x, In tp1 (timed m) -> In tp2 (timed m) ->
  In x (clock_names tp1) -> In x (clock_names tp2) -> tp1 = tp2.
Proof.
  intros tp1 tp2 x H1 H2 X1 X2. destruct (NoDup_app_inv _ _ _ msgs_clocks_nodup) as (_ & N & _).
  eapply NoDup_flat_map_in; eauto.
Qed.

Lemma msg_not_clock:
  forall tp1 tp2 x, In tp1 (subscribed m) -> In tp2 (timed m) -> In x (clock_names tp2) ->
  msg_var (tp_cname tp1) <> x.
Proof.
  intros tp1 tp2 x H1 H2 X E. destruct (NoDup_app_inv _ _ _ msgs_clocks_nodup) as (_ & _ & D).
  apply (D x).
  - rewrite <- E. apply (in_map (fun tp => msg_var (tp_cname tp))); auto.
  - apply in_flat_map; eauto.
Qed.

Lemma controller_not_clock:
  forall tp x, In tp (timed m) -> In x (clock_names tp) -> x <> nm_in_var m /\ x <> nm_out_var m.
Proof.
  intros tp x H X. destruct (wf_controller_vars_fresh m W) as (_ & NU & NY).
  split; intros ->; [apply NU|apply NY]; eapply clock_name_in_after; eauto.
Qed.

Lemma timed_subscribed: forall tp, In tp (timed m) -> In tp (subscribed m).
Proof. apply (gen_timed_sub m). Qed.

(** *** Globals changed one after the other *)

Lemma global_value_same:
  forall mm mm' y,
  (forall by_ ty, find_var ge y = Some (by_, ty) -> get_block mm' by_ = get_block mm by_) ->
  global_value p mm' y = global_value p mm y.
Proof.
  intros mm mm' y H. unfold global_value. destruct (find_var ge y) as [[b ty]|] eqn:V; auto.
  rewrite (H b ty); auto.
Qed.

Lemma only_global_other:
  forall mm mm' x v y, only_global_changed p mm mm' x v -> y <> x ->
  global_value p mm' y = global_value p mm y.
Proof.
  intros mm mm' x v y (bx & tx & Vx & Gx & [Nn No]) N. apply global_value_same.
  intros by_ ty Vy. apply No. intros ->. eapply (globalenv_vars_disjoint p y x); eauto.
Qed.

Lemma only_global_same:
  forall mm mm' x v, only_global_changed p mm mm' x v -> global_value p mm' x = Some v.
Proof. intros mm mm' x v (bx & tx & Vx & Gx & _). unfold global_value. rewrite Vx, Gx. auto. Qed.

Lemma globals_changed_next:
  forall mm mm' l, globals_changed p mm mm' l -> mem_next mm' = mem_next mm.
Proof.
  intros mm mm' l H; induction H as [|mm mm1 mm' x v l (bx & tx & _ & _ & [N _]) _ IH]; congruence.
Qed.

Lemma globals_changed_other:
  forall mm mm' l, globals_changed p mm mm' l ->
  forall b, not_global p b -> get_block mm' b = get_block mm b.
Proof.
  intros mm mm' l H; induction H as [|mm mm1 mm' x v l (bx & tx & Vx & _ & [_ O]) _ IH]; intros b NG; auto.
  rewrite IH by auto. apply O. intros E; subst. apply (NG _ _ _ Vx); auto.
Qed.

Lemma globals_changed_value:
  forall mm mm' l, globals_changed p mm mm' l -> NoDup (map fst l) ->
  forall y, global_value p mm' y = match find_assoc y l with Some v => Some v | None => global_value p mm y end.
Proof.
  intros mm mm' l H; induction H as [|mm mm1 mm' x v l OG _ IH]; intros NDl y; auto.
  simpl in NDl. inversion NDl as [|? ? Hn NDl']; subst. rewrite IH by auto. simpl.
  destruct (string_dec y x) as [->|N].
  - rewrite find_assoc_notin by auto. eapply only_global_same; eauto.
  - destruct (find_assoc y l); auto. eapply only_global_other; eauto.
Qed.

Lemma globals_changed_notin:
  forall mm mm' l, globals_changed p mm mm' l ->
  forall y, ~ In y (map fst l) -> global_value p mm' y = global_value p mm y.
Proof.
  intros mm mm' l H; induction H as [|mm mm1 mm' x v l OG _ IH]; intros y Ny; auto.
  simpl in Ny. rewrite IH by tauto. eapply only_global_other; eauto.
Qed.

Lemma globals_changed_typed:
  forall mm mm' l, globals_changed p mm mm' l -> mem_wf mm -> globals_typed p mm ->
  (forall x v, In (x, v) l -> forall b ty, find_var ge x = Some (b, ty) -> mval_has_type ce ty v) ->
  mem_wf mm' /\ globals_typed p mm'.
Proof.
  intros mm mm' l H; induction H as [|mm mm1 mm' x v l OG _ IH]; intros Wm GT Tv; auto.
  assert (GT1: globals_typed p mm1).
  { eapply (globals_typed_changed m p GEN); eauto. intros b ty V. eapply Tv; simpl; eauto. }
  destruct OG as (bx & tx & Vx & Gx & U) eqn:E0.
  assert (W1: mem_wf mm1).
  { eapply mem_wf_unchanged; eauto. eapply global_var_block; eauto. }
  apply IH; auto. intros; eapply Tv; simpl; eauto.
Qed.

(** The clock globals of a timed topic, read in a memory. *)
Lemma clock_held_same:
  forall mm mm' tp b r, (forall x, In x (clock_names tp) -> global_value p mm' x = global_value p mm x) ->
  clock_held p mm (tp_cname tp) b r -> clock_held p mm' (tp_cname tp) b r.
Proof.
  intros mm mm' tp b r H (A & B & C). unfold clock_held.
  rewrite (H (new_var (tp_cname tp))), (H (rcvd_var (tp_cname tp))) by (simpl; auto).
  split; auto; split; auto. intros t E. rewrite (H (time_var (tp_cname tp))) by (simpl; auto). auto.
Qed.

Lemma msg_global:
  forall tp, In tp (subscribed m) -> exists bg, find_var ge (msg_var (tp_cname tp)) = Some (bg, Tstruct (tp_msg tp)).
Proof.
  intros tp H. destruct (generate_callback m p tp GEN H) as [Fv _]. apply (gen_var m p GEN _ _ Fv).
Qed.

Lemma zero_shape:
  forall tp v, In tp (nm_topics m) -> mval_has_type ce (Tstruct (tp_msg tp)) v ->
  mval_shape v = undef_mval ce (Tstruct (tp_msg tp)).
Proof.
  intros tp v H T. rewrite <- (shape_zero_mval ce).
  apply (mval_shape_typed ce v (Tstruct (tp_msg tp))); auto.
  apply (gen_zero_typed m p GEN). apply (gen_msg_in m p GEN); auto.
Qed.

(** *** Clocks *)

(** The receipt time of the newest message received in the first [k]
    spins ([None] before the first). *)
Definition held_time (tp : topic) (k : nat) : option Z :=
  match k with O => None | S i => newest_time m ctx tp i end.

Lemma newest_time_step:
  forall tp k,
  newest_time m ctx tp k
  = match last_on (tp_name tp) (received_on m tp (ctx_arrivals ctx k)) with
    | Some a => Some (ar_time a)
    | None => held_time tp k
    end.
Proof.
  intros tp k. unfold newest_time, newest_arrival.
  rewrite seq_S, flat_map_app. simpl. rewrite app_nil_r, last_on_app.
  destruct (last_on (tp_name tp) (received_on m tp (ctx_arrivals ctx k))); auto.
  destruct k as [|i]; simpl; auto.
Qed.

(** The [c_new] flags: all clear, or set for the topics on which a
    message arrived for spin [k]. *)
Definition nonew (tp : topic) : bool := false.
Definition arrived_at (k : nat) (tp : topic) : bool := arrived m ctx tp k.

(** *** The invariant of the loop *)

(** [g] and [h] agree on the paths of topic [tp] that the node reads. *)
Definition reads_agree (tp : topic) (g h : mval) : Prop :=
  forall lp, In lp (read_paths m (tp_cname tp)) -> mval_get g (path_steps lp) = mval_get h (path_steps lp).

(** What the node reads of a subscribed topic are leaves of its messages. *)
Lemma read_path_leaf:
  forall tp lp, In tp (subscribed m) -> In lp (read_paths m (tp_cname tp)) ->
  exists q, resolve (nm_msgs m) (FTmsg (tp_msg tp)) lp = Some (FTprim q).
Proof.
  intros tp lp Hs Hr.
  assert (FT: find_topic (nm_topics m) (tp_cname tp) = Some tp)
    by (apply In_find_topic; [apply wf_cnames_nodup; auto|apply in_subscribed in Hs; tauto]).
  unfold read_paths in Hr. apply in_app_iff in Hr as [Hr|Hr].
  - apply in_map_iff in Hr as (ir & <- & Hir). apply filter_In in Hir as [Hir E]. apply ident_eqb_true in E.
    apply incl_glue_inrels in Hir.
    destruct (input_exprs m ir W Hir) as (tp' & t & q & F' & _ & _ & _ & _ & R & _).
    rewrite E, FT in F'. inversion F'; subst. eauto.
  - apply in_flat_map in Hr as ([c [s0 sp]] & Hin & Hr). cbn [fst snd] in Hr.
    destruct (ident_eqb s0 (tp_cname tp)) eqn:E; [|contradiction].
    apply ident_eqb_true in E; subst s0.
    destruct (wf_stamp_from m _ _ _ W Hin) as (tp' & F' & _ & Rs & Rn & _). rewrite FT in F'. inversion F'; subst.
    destruct Hr as [<-|[<-|[]]]; eauto.
Qed.

Record loop_inv (k : nat) (nw : topic -> bool) (e : env) (mm : mem) : Prop := {
  li_wf: mem_wf mm;
  li_globals: globals_typed p mm;
  li_msgs: forall tp, In tp (subscribed m) ->
             exists g, global_value p mm (msg_var (tp_cname tp)) = Some g /\ reads_agree tp g (held m ctx tp k);
  li_cmds: forall tp, In tp (published m) ->
             exists b, find_assoc (cmd_var (tp_cname tp)) e = Some (b, Tstruct (tp_msg tp))
             /\ not_global p b
             /\ exists v, get_block mm b = Some (Tstruct (tp_msg tp), v)
                          /\ mval_shape v = undef_mval ce (Tstruct (tp_msg tp));
  li_clock: forall tp, In tp (timed m) -> clock_held p mm (tp_cname tp) (nw tp) (held_time tp k);
  li_funs: forall x, In x (map fst (prog_defs p)) -> find_assoc x e = None;
  li_direct: forall tp ir, In tp (subscribed m) -> In ir (direct_of m (tp_cname tp)) ->
               mval_get (global_inputs m p mm) (input_leaf ir) = mval_get (held m ctx tp k) (path_steps (ir_path ir))
}.

Arguments li_wf {k nw e mm}.
Arguments li_globals {k nw e mm}.
Arguments li_msgs {k nw e mm}.
Arguments li_cmds {k nw e mm}.
Arguments li_clock {k nw e mm}.
Arguments li_funs {k nw e mm}.
Arguments li_direct {k nw e mm}.

(** Replacing the value of a global that is not a topic's message by a
    value of its type keeps the invariant. *)
Lemma inv_change_global_gen:
  forall k nw nw' e mm mm' x v,
  loop_inv k nw e mm -> only_global_changed p mm mm' x v ->
  (forall tp, In tp (subscribed m) -> msg_var (tp_cname tp) <> x) ->
  (x = nm_in_var m -> forall tp ir, In tp (subscribed m) -> In ir (direct_of m (tp_cname tp)) ->
     mval_get v (input_leaf ir) = mval_get (global_inputs m p mm) (input_leaf ir)) ->
  (forall b ty, find_var ge x = Some (b, ty) -> mval_has_type ce ty v) ->
  (forall tp, In tp (timed m) -> clock_held p mm' (tp_cname tp) (nw' tp) (held_time tp k)) ->
  loop_inv k nw' e mm'.
Proof.
  intros k nw nw' e mm mm' x v I OG NM DIR Tv CL.
  assert (OG' := OG).
  destruct OG as (bx & tx & Vx & Gx & [Nn No]).
  assert (Lx: get_block mm bx <> None) by (eapply global_var_block; [apply (li_globals I) | eauto]).
  constructor.
  - eapply mem_wf_unchanged; [apply (li_wf I) | split; eauto | auto].
  - intros y b ty Vy. destruct (Pos.eq_dec b bx) as [->|Nb].
    + destruct (find_var_same_block _ _ _ _ _ Vx Vy) as [-> ->]. exists v; split; auto.
      rewrite types_eq; auto. eapply Tv; eauto.
    + rewrite No; auto. apply (li_globals I _ _ _ Vy).
  - intros tp Htp. generalize (li_msgs I tp Htp). unfold global_value.
    destruct (find_var ge (msg_var (tp_cname tp))) as [[bg ty]|] eqn:Vg; auto.
    rewrite No; auto. intros E; subst bg.
    destruct (find_var_same_block _ _ _ _ _ Vx Vg) as [E _]. apply (NM tp Htp); auto.
  - intros tp Htp. destruct (li_cmds I tp Htp) as (b & F & NG & v' & G & S).
    exists b; split; auto; split; auto. exists v'; split; auto.
    rewrite No; auto. intros E; subst b. apply (NG _ _ _ Vx); auto.
  - exact CL.
  - apply (li_funs I).
  - intros tp ir Htp Hd. rewrite <- (li_direct I tp ir Htp Hd).
    destruct (string_dec x (nm_in_var m)) as [Ex|NU].
    + rewrite <- (DIR Ex tp ir Htp Hd). unfold global_inputs. rewrite <- Ex, (only_global_same _ _ _ _ OG'). reflexivity.
    + unfold global_inputs.
      rewrite (global_value_same mm mm' (nm_in_var m)); [reflexivity|]. intros by_ ty V. apply No. intros ->.
      apply (globalenv_vars_disjoint p (nm_in_var m) x bx ty bx tx V Vx); auto.
Qed.


Lemma inv_change_global:
  forall k nw e mm mm' x v,
  loop_inv k nw e mm -> only_global_changed p mm mm' x v ->
  (forall tp, In tp (subscribed m) -> msg_var (tp_cname tp) <> x) ->
  (forall tp y, In tp (timed m) -> In y (clock_names tp) -> y <> x) ->
  x <> nm_in_var m ->
  (forall b ty, find_var ge x = Some (b, ty) -> mval_has_type ce ty v) ->
  loop_inv k nw e mm'.
Proof.
  intros k nw e mm mm' x v I OG NM NC NU Tv.
  apply (inv_change_global_gen k nw nw e mm mm' x v I OG NM ltac:(intros E; congruence) Tv).
  intros tp Ht. apply clock_held_same with mm; [|apply (li_clock I tp Ht)].
  intros y Hy. eapply only_global_other; eauto.
Qed.

(** The [c_new] flags only matter for the timed topics. *)
Lemma loop_inv_ext:
  forall k nw1 nw2 e mm, (forall tp, In tp (timed m) -> nw1 tp = nw2 tp) ->
  loop_inv k nw1 e mm -> loop_inv k nw2 e mm.
Proof.
  intros k nw1 nw2 e mm H I. constructor; try apply I.
  intros tp Ht. rewrite <- (H tp Ht). apply (li_clock I tp Ht).
Qed.

(** Clearing the [c_new] flag of a timed topic. *)
Lemma inv_reset_one:
  forall k nw e mm mm1 tp0,
  loop_inv k nw e mm -> In tp0 (timed m) ->
  only_global_changed p mm mm1 (new_var (tp_cname tp0)) (MVscalar (Vint 0)) ->
  loop_inv k (fun tp => if ident_eqb (tp_cname tp0) (tp_cname tp) then false else nw tp) e mm1.
Proof.
  intros k nw e mm mm1 tp0 I Ht0 OG.
  assert (Hs0 := timed_subscribed tp0 Ht0).
  assert (NM: forall tp, In tp (subscribed m) -> msg_var (tp_cname tp) <> new_var (tp_cname tp0)).
  { intros tp Htp. apply (msg_not_clock tp tp0); simpl; auto. }
  apply (inv_change_global_gen k nw _ e mm mm1 (new_var (tp_cname tp0)) (MVscalar (Vint 0)) I OG NM).
  { intros E. exfalso. apply (proj1 (controller_not_clock tp0 _ Ht0 (or_intror (or_introl eq_refl)))); auto. }
  - intros b ty V. destruct (generate_clock_globals m p tp0 GEN Ht0) as (_ & Fn & _).
    destruct (gen_var m p GEN _ _ Fn) as [b' V']. rewrite V' in V. inversion V; subst.
    constructor; reflexivity.
  - intros tp Ht. destruct (li_clock I tp Ht) as (A & B & C).
    destruct (ident_eqb (tp_cname tp0) (tp_cname tp)) eqn:E.
    + apply ident_eqb_true in E.
      assert (tp0 = tp).
      { apply (NoDup_map_inj_in _ _ tp_cname (nm_topics m)); auto.
        - apply wf_cnames_nodup; auto.
        - apply in_subscribed in Hs0; tauto.
        - apply (in_subscribed m tp). apply timed_subscribed; auto. }
      subst tp0.
      destruct (clock_names_distinct (tp_cname tp)) as (A1 & A2 & A3 & _).
      split; [|split].
      * eapply only_global_same; eauto.
      * rewrite (only_global_other _ _ _ _ (rcvd_var (tp_cname tp)) OG); auto.
      * intros t Et. rewrite (only_global_other _ _ _ _ (time_var (tp_cname tp)) OG); auto.
    + apply clock_held_same with mm; [|split; auto].
      intros y Hy. apply (only_global_other _ _ _ _ y OG). intros Ey. subst y.
      assert (tp = tp0) by (apply (clock_name_topic tp tp0 (new_var (tp_cname tp0))); simpl; auto).
      subst tp0. rewrite ident_eqb_refl in E. discriminate.
Qed.

(** Clearing the [c_new] flags of timed topics. *)
Lemma inv_resets:
  forall k L nw e mm mm', incl L (timed m) -> loop_inv k nw e mm ->
  globals_changed p mm mm' (map (fun tp => (new_var (tp_cname tp), MVscalar (Vint 0))) L) ->
  loop_inv k (fun tp => if existsb (fun t => ident_eqb (tp_cname t) (tp_cname tp)) L then false else nw tp) e mm'.
Proof.
  intros k L; induction L as [|tp0 L IH]; intros nw e mm mm' Inc I GC; simpl in GC.
  - inversion GC; subst. apply (loop_inv_ext k nw); auto.
  - inversion GC as [|? mm1 ? ? ? ? OG GC']; subst.
    assert (Ht0: In tp0 (timed m)) by (apply Inc; simpl; auto).
    generalize (IH _ e mm1 mm' (fun x H => Inc x (or_intror H)) (inv_reset_one k nw e mm mm1 tp0 I Ht0 OG) GC').
    apply loop_inv_ext. intros tp _. simpl.
    destruct (ident_eqb (tp_cname tp0) (tp_cname tp)); simpl;
      destruct (existsb _ L); auto.
Qed.

(** *** [ros_spinOnce] *)

(** The deliveries of [D] whose callback is called ([Environment.accepted]). *)
Definition accepted_in (D : list (subscription * arrival)) : list (subscription * arrival) :=
  filter (fun sa => accepted ge (fst sa) (snd sa)) D.

Lemma deliver_run:
  forall D (w : world CS) mm (G : topic -> mval) (C : topic -> bool * option Z),
  mem_wf mm -> globals_typed p mm ->
  (forall tp, In tp (subscribed m) ->
     exists g, global_value p mm (msg_var (tp_cname tp)) = Some g /\ reads_agree tp g (G tp)) ->
  (forall tp ir, In tp (subscribed m) -> In ir (direct_of m (tp_cname tp)) ->
     mval_get (global_inputs m p mm) (input_leaf ir) = mval_get (G tp) (path_steps (ir_path ir))) ->
  (forall tp, In tp (timed m) -> clock_held p mm (tp_cname tp) (fst (C tp)) (snd (C tp))) ->
  (forall s a, In (s, a) D ->
     exists tp, In tp (subscribed m) /\ s = sub_of tp /\ mval_has_type ce (Tstruct (tp_msg tp)) (ar_msg a)) ->
  exists mm' w',
     deliver ctx ge mm w D [] mm' w'
  /\ next_spin ctx w' = next_spin ctx w
  /\ mem_wf mm' /\ globals_typed p mm'
  /\ (forall tp, In tp (subscribed m) ->
        exists g, global_value p mm' (msg_var (tp_cname tp)) = Some g
        /\ reads_agree tp g (match last_delivered (sub_of tp) (accepted_in D) with Some a => converted m tp a | None => G tp end))
  /\ (forall tp ir, In tp (subscribed m) -> In ir (direct_of m (tp_cname tp)) ->
        mval_get (global_inputs m p mm') (input_leaf ir)
        = mval_get (match last_delivered (sub_of tp) (accepted_in D) with Some a => converted m tp a | None => G tp end)
                   (path_steps (ir_path ir)))
  /\ (forall tp, In tp (timed m) ->
        clock_held p mm' (tp_cname tp)
          (match last_delivered (sub_of tp) (accepted_in D) with Some _ => true | None => fst (C tp) end)
          (match last_delivered (sub_of tp) (accepted_in D) with Some a => Some (ar_time a) | None => snd (C tp) end))
  /\ (forall b, get_block mm b <> None -> not_global p b -> get_block mm' b = get_block mm b).
Proof.
  intros D; induction D as [|[s a] D IH]; intros w mm G C Wm GT HG HU HC HD.
  - exists mm, w. split; [apply deliver_nil|]. split; [auto|]. split; [auto|]. split; [auto|].
    split; [auto|]. split; [auto|]. split; [intros tp Ht; exact (HC tp Ht)|auto].
  - destruct (HD s a (or_introl eq_refl)) as (tp' & Htp' & -> & Tmv0).
    destruct (accepted ge (sub_of tp') a) eqn:Acc.
    2:{ destruct (IH w mm G C Wm GT HG HU HC) as (mm' & w' & X & R); [intros s0 a0 H0; apply HD; simpl; auto|].
        exists mm', w'. split; [apply deliver_rejected; auto|].
        unfold accepted_in; cbn [filter fst snd]; rewrite Acc. exact R. }
    assert (AD: accepted_in ((sub_of tp', a) :: D) = (sub_of tp', a) :: accepted_in D)
      by (unfold accepted_in; cbn [filter fst snd]; rewrite Acc; reflexivity).
    rewrite AD.
    set (mv := converted m tp' a).
    assert (Tmv: mval_has_type ce (Tstruct (tp_msg tp')) mv) by (apply clamp_typed; [apply (gen_wf_composites m p GEN) | exact Tmv0]).
    assert (Dv: delivered ge (sub_of tp') a = mv)
      by (unfold delivered, mv, converted; rewrite globalenv_comp, types_eq; reflexivity).
    destruct (generate_callback_ddc m p GEN tp' Htp') as (f' & Ff' & Spec).
    destruct (alloc mm (Tstruct (tp_msg tp')) mv) as [m1 bn] eqn:AL.
    assert (Ebn: bn = mem_next mm) by (eapply alloc_result; eauto).
    assert (Glob: forall x bx tx, find_var ge x = Some (bx, tx) -> bx <> bn).
    { intros x bx tx V E. subst bx. destruct (GT _ _ _ V) as (v & Gv & _).
      rewrite (Wm bn) in Gv; [discriminate|]. lia. }
    assert (GT1: globals_typed p m1).
    { intros x bx tx V. rewrite (get_block_alloc_other _ _ _ _ _ _ AL) by (eapply Glob; eauto).
      apply (GT _ _ _ V). }
    assert (GV1: forall y, global_value p m1 y = global_value p mm y).
    { intros y. apply global_value_same. intros by_ ty V.
      apply (get_block_alloc_other _ _ _ _ _ _ AL). eapply Glob; eauto. }
    assert (G1: get_block m1 bn = Some (Tstruct (tp_msg tp'), mv)) by (eapply get_block_alloc_same; eauto).
    assert (W1: mem_wf m1) by (eapply mem_wf_alloc; eauto).
    destruct (Spec m1 bn mv GT1 Glob G1 ltac:(rewrite types_eq; auto) CS ctx (set_time w (ar_time a)))
      as [[t1 [m2 [w1 [v1 X1]]]] All].
    destruct (All t1 m2 w1 v1 X1) as (-> & -> & -> & (g' & u' & GC & Tg' & RC & Tu' & DC)).
    rewrite types_eq in Tg', Tu'.
    cbn [w_time set_time] in GC.
    set (l := (msg_var (tp_cname tp'), g') :: (nm_in_var m, u') :: clock_update m (tp_cname tp') (ar_time a)) in GC.
    assert (NUm: msg_var (tp_cname tp') <> nm_in_var m) by apply (proj1 (gen_in_out_vars m p GEN tp' Htp')).
    assert (NDl: NoDup (map fst l)).
    { unfold l, clock_update. destruct (is_timed m (tp_cname tp')) eqn:T; simpl;
        [|repeat constructor; simpl; intuition congruence].
      assert (Ht: In tp' (timed m)) by (apply filter_In; auto).
      destruct (clock_names_distinct (tp_cname tp')) as (A1 & A2 & A3 & A4 & A5 & A6).
      destruct (controller_not_clock tp' _ Ht (or_introl eq_refl)) as [C1 _].
      destruct (controller_not_clock tp' _ Ht (or_intror (or_introl eq_refl))) as [C2 _].
      destruct (controller_not_clock tp' _ Ht (or_intror (or_intror (or_introl eq_refl)))) as [C3 _].
      repeat constructor; simpl; intuition congruence. }
    assert (TL: forall x v, In (x, v) l -> forall b ty, find_var ge x = Some (b, ty) -> mval_has_type ce ty v).
    { intros x v Hx b ty V. unfold l in Hx. destruct Hx as [E|[E|Hx]].
      - inversion E; subst. destruct (msg_global tp' Htp') as [bg Vg]. rewrite Vg in V. inversion V; subst. auto.
      - inversion E; subst. destruct (generate_externals m p GEN) as (_ & _ & _ & _ & _ & _ & Fu & _).
        destruct (gen_var m p GEN _ _ Fu) as [bu' Vu']. rewrite Vu' in V. inversion V; subst. auto.
      - unfold clock_update in Hx. destruct (is_timed m (tp_cname tp')) eqn:T; [|contradiction].
        assert (Ht: In tp' (timed m)) by (apply filter_In; auto).
        destruct (generate_clock_globals m p tp' GEN Ht) as (Ft & Fn & Fr).
        destruct Hx as [E|[E|[E|[]]]]; inversion E; subst;
          [destruct (gen_var m p GEN _ _ Ft) as [b' V']|destruct (gen_var m p GEN _ _ Fn) as [b' V']
          |destruct (gen_var m p GEN _ _ Fr) as [b' V']];
          rewrite V' in V; inversion V; subst; constructor; try reflexivity.
        unfold val_has_type, clock. apply norm_long_idem. }
    destruct (globals_changed_typed m1 m2 l GC W1 GT1 TL) as [W2 GT2].
    assert (GV2 := globals_changed_value m1 m2 l GC NDl).
    set (m3 := free m2 bn).
    assert (GV3: forall y, global_value p m3 y = global_value p m2 y).
    { intros y. apply global_value_same. intros by_ ty V. unfold m3.
      apply get_block_free_other. eapply Glob; eauto. }
    assert (GT3: globals_typed p m3).
    { intros x bx tx V. unfold m3. rewrite get_block_free_other by (eapply Glob; eauto). apply (GT2 _ _ _ V). }
    set (G1f := fun tp => if sub_eq (sub_of tp') (sub_of tp) then mv else G tp).
    set (C1f := fun tp => if sub_eq (sub_of tp') (sub_of tp) then (true, Some (ar_time a)) else C tp).
    assert (HG3: forall tp, In tp (subscribed m) ->
              exists g, global_value p m3 (msg_var (tp_cname tp)) = Some g /\ reads_agree tp g (G1f tp)).
    { intros tp Htp. rewrite GV3, GV2. unfold G1f.
      destruct (sub_eq (sub_of tp') (sub_of tp)) as [E|E].
      - assert (tp' = tp) by (apply callback_inj; auto; inversion E; auto). subst tp'.
        exists g'. split; [unfold l; simpl; destruct (string_dec _ _); [auto|congruence]|].
        intros lp Hr. destruct (read_path_leaf tp lp Htp Hr) as (q & R).
        rewrite (RC lp q R). replace (is_read m (tp_cname tp) lp) with true; auto.
        symmetry; apply is_read_In; auto.
      - destruct (HG tp Htp) as (g0 & G0 & A0). exists g0. split; [|exact A0]. revert G0.
        unfold l. simpl. destruct (string_dec (msg_var (tp_cname tp)) (msg_var (tp_cname tp'))) as [E'|N'].
        + exfalso. apply E. f_equal. apply msg_var_inj; auto.
        + destruct (string_dec (msg_var (tp_cname tp)) (nm_in_var m)) as [E3|_];
            [elim (proj1 (gen_in_out_vars m p GEN tp Htp)); auto|].
          unfold clock_update. destruct (is_timed m (tp_cname tp')) eqn:T; simpl.
          * assert (Ht: In tp' (timed m)) by (apply filter_In; auto).
            assert (NC: forall x, In x (clock_names tp') -> msg_var (tp_cname tp) <> x)
              by (intros x Hx; apply (msg_not_clock tp tp' x); auto).
            destruct (string_dec _ (time_var _)) as [E2|_]; [elim (NC _ (or_introl eq_refl)); auto|].
            destruct (string_dec _ (new_var _)) as [E2|_]; [elim (NC _ (or_intror (or_introl eq_refl))); auto|].
            destruct (string_dec _ (rcvd_var _)) as [E2|_];
              [elim (NC _ (or_intror (or_intror (or_introl eq_refl)))); auto|].
            rewrite GV1. auto.
          * rewrite GV1. auto. }
    assert (HC3: forall tp, In tp (timed m) -> clock_held p m3 (tp_cname tp) (fst (C1f tp)) (snd (C1f tp))).
    { intros tp Ht. unfold C1f. destruct (sub_eq (sub_of tp') (sub_of tp)) as [E|E].
      - assert (tp' = tp) by (apply callback_inj; auto; [apply timed_subscribed; auto|inversion E; auto]).
        subst tp'. assert (T: is_timed m (tp_cname tp) = true) by (apply (gen_timed_is m); auto).
        destruct (clock_names_distinct (tp_cname tp)) as (A1 & A2 & A3 & A4 & A5 & A6).
        destruct (controller_not_clock tp _ Ht (or_introl eq_refl)) as [C1 _].
        destruct (controller_not_clock tp _ Ht (or_intror (or_introl eq_refl))) as [C2 _].
        destruct (controller_not_clock tp _ Ht (or_intror (or_intror (or_introl eq_refl)))) as [C3 _].
        unfold clock_held. cbn [fst snd]. rewrite !GV3, !GV2. unfold l, clock_update. rewrite T. simpl.
        repeat split.
        + repeat (destruct (string_dec _ _); try congruence).
        + repeat (destruct (string_dec _ _); try congruence).
        + intros t Et. inversion Et; subst. repeat (destruct (string_dec _ _); try congruence).
      - apply clock_held_same with mm; [|apply HC; auto].
        intros x Hx. rewrite GV3, GV2, GV1. unfold l. simpl.
        destruct (string_dec x (msg_var (tp_cname tp'))) as [Ex|Nx].
        + exfalso. apply (msg_not_clock tp' tp x); auto; congruence.
        + destruct (string_dec x (nm_in_var m)) as [Ex2|_]; [exfalso; apply (proj1 (controller_not_clock tp x Ht Hx)); auto|].
          unfold clock_update. destruct (is_timed m (tp_cname tp')) eqn:T; simpl; auto.
          assert (Ht': In tp' (timed m)) by (apply filter_In; auto).
          assert (NC: forall y, In y (clock_names tp') -> x <> y).
          { intros y Hy Exy. subst y. apply E. f_equal. apply (clock_name_topic tp' tp x); auto. }
          destruct (string_dec _ (time_var _)) as [E2|_]; [elim (NC _ (or_introl eq_refl)); auto|].
          destruct (string_dec _ (new_var _)) as [E2|_]; [elim (NC _ (or_intror (or_introl eq_refl))); auto|].
          destruct (string_dec _ (rcvd_var _)) as [E2|_];
            [elim (NC _ (or_intror (or_intror (or_introl eq_refl)))); auto|].
          auto. }
    assert (HU3: forall tp ir, In tp (subscribed m) -> In ir (direct_of m (tp_cname tp)) ->
              mval_get (global_inputs m p m3) (input_leaf ir) = mval_get (G1f tp) (path_steps (ir_path ir))).
    { intros tp ir Htp Hd.
      assert (GU3: global_inputs m p m3 = u').
      { unfold global_inputs. rewrite GV3, GV2. unfold l. simpl.
        destruct (string_dec (nm_in_var m) (msg_var (tp_cname tp'))) as [E|_]; [congruence|].
        destruct (string_dec (nm_in_var m) (nm_in_var m)); [reflexivity|congruence]. }
      rewrite GU3. unfold G1f. destruct DC as [DC1 DC2].
      destruct (sub_eq (sub_of tp') (sub_of tp)) as [E|E].
      - assert (tp' = tp) by (apply callback_inj; auto; inversion E; auto). subst tp'. apply DC1; auto.
      - rewrite DC2.
        + rewrite <- (HU tp ir Htp Hd). unfold global_inputs. rewrite GV1. reflexivity.
        + intros ir' Hd'. apply (input_leaves_distinct m p GEN).
          * apply direct_of_In in Hd'; tauto.
          * apply direct_of_In in Hd; tauto.
          * intros ->. apply direct_of_In in Hd' as (_ & E1 & _). apply direct_of_In in Hd as (_ & E2 & _).
            apply E. f_equal.
            apply (NoDup_map_inj_in _ _ tp_cname (nm_topics m)); auto.
            -- apply wf_cnames_nodup; auto.
            -- apply in_subscribed in Htp'; tauto.
            -- apply in_subscribed in Htp; tauto.
            -- congruence. }
    destruct (IH (set_time w (ar_time a)) m3 G1f C1f (mem_wf_free _ _ W2) GT3 HG3 HU3 HC3)
      as (mm' & w' & X & NS & W' & GT' & HG' & HU' & HC' & Fr').
    { intros s0 mv0 H0. apply HD; simpl; auto. }
    exists mm', w'. refine (conj _ (conj NS (conj W' (conj GT' (conj _ (conj _ (conj _ _))))))).
    + change (@nil event) with (@nil event ++ @nil event). econstructor; [exact Acc|cbn [sub_msgty sub_of]; rewrite Dv; exact AL|eauto..].
    + intros tp Htp. destruct (HG' tp Htp) as (g & Gg & Ag). exists g; split; [exact Gg|]. revert Ag.
      cbn [last_delivered]. unfold G1f.
      destruct (last_delivered (sub_of tp) (accepted_in D)); auto.
      destruct (sub_eq (sub_of tp') (sub_of tp)) as [E|]; auto.
      assert (tp' = tp) by (apply callback_inj; auto; inversion E; auto). subst tp'. auto.
    + intros tp ir Htp Hd. rewrite (HU' tp ir Htp Hd). cbn [last_delivered]. unfold G1f.
      destruct (last_delivered (sub_of tp) (accepted_in D)); auto.
      destruct (sub_eq (sub_of tp') (sub_of tp)) as [E|]; auto.
      assert (tp' = tp) by (apply callback_inj; auto; inversion E; auto). subst tp'. auto.
    + intros tp Ht. generalize (HC' tp Ht). cbn [last_delivered]. unfold C1f.
      destruct (last_delivered (sub_of tp) (accepted_in D)); auto.
      destruct (sub_eq (sub_of tp') (sub_of tp)); auto.
    + intros b Lb NG. rewrite Fr'.
      * unfold m3. rewrite get_block_free_other by (intros ->; apply Lb; apply Wm; lia).
        rewrite (globals_changed_other m1 m2 l GC b NG).
        apply (get_block_alloc_other _ _ _ _ _ _ AL). intros ->. apply Lb. apply Wm. lia.
      * unfold m3. rewrite get_block_free_other by (intros ->; apply Lb; apply Wm; lia).
        rewrite (globals_changed_other m1 m2 l GC b NG).
        rewrite (get_block_alloc_other _ _ _ _ _ _ AL); auto. intros ->. apply Lb. apply Wm. lia.
      * auto.
Qed.

(** The last message that the callback of a subscribed topic is called
    with in one spin is the last one that the topic's queue keeps and the
    node accepts ([received_on]). *)
Lemma last_accepted_deliverable:
  forall tp msgs, In tp (subscribed m) ->
  last_delivered (sub_of tp) (accepted_in (deliverable subs_of msgs)) = last_on (tp_name tp) (received_on m tp msgs).
Proof.
  intros tp msgs Htp. assert (Hs: In (sub_of tp) subs_of) by (unfold subs_of; apply in_map; auto).
  assert (Acc: forall a, accepted ge (sub_of tp) a = negb (too_long (composites m) (Tstruct (tp_msg tp)) (ar_msg a)))
    by (intros a; unfold accepted; rewrite globalenv_comp, types_eq; reflexivity).
  induction msgs as [|a rest IH]; [reflexivity|].
  cbn [deliverable received_on]. unfold accepted_in in *. rewrite filter_app, last_delivered_app, IH, last_on_app.
  destruct (last_on (tp_name tp) (received_on m tp rest)) as [v|]; [reflexivity|].
  rewrite last_delivered_filter_map. cbn [fst snd]. rewrite Acc.
  destruct (in_dec sub_eq (sub_of tp) _) as [H|H].
  - apply filter_In in H as [_ H]. apply andb_true_iff in H as [T K].
    unfold topic_eqb in T |- *. cbn [sub_topic sub_of] in T.
    destruct (string_dec (tp_name tp) (ar_topic a)) as [E|]; [|discriminate].
    unfold keeps in K. cbn [sub_queue sub_of] in K. rewrite <- E in K.
    destruct (string_dec (ar_topic a) (tp_name tp)) as [_|N]; [|congruence].
    rewrite K. cbn [andb].
    destruct (negb (too_long (composites m) (Tstruct (tp_msg tp)) (ar_msg a))); [|reflexivity].
    simpl. destruct (string_dec (ar_topic a) (tp_name tp)); congruence.
  - unfold topic_eqb.
    destruct (string_dec (ar_topic a) (tp_name tp)) as [E|]; [|reflexivity].
    replace (Nat.eqb (tp_queue tp) 0 || Nat.ltb (count_topic (tp_name tp) rest) (tp_queue tp)) with false; [reflexivity|].
    symmetry. apply not_true_iff_false. intros K. apply H. apply filter_In. split; auto.
    unfold topic_eqb, keeps. cbn [sub_topic sub_queue sub_of].
    destruct (string_dec (tp_name tp) (ar_topic a)); [|congruence]. rewrite E. exact K.
Qed.

(** The same on ROS 2: the subscriptions are distinct (their callbacks
    are), so the spin hands each callback what its history keeps, in
    take order, and a history of depth at least 1 (the generator's rule)
    keeps the newest message. *)
Lemma subs_of_nodup: NoDup subs_of.
Proof.
  apply (NoDup_map_inv sub_callback). unfold subs_of. rewrite map_map. cbn [sub_callback sub_of].
  generalize global_names_nodup; unfold global_names; intros N.
  do 6 apply NoDup_app_right in N. apply NoDup_app_left in N. exact N.
Qed.

Lemma last_accepted_rcl_deliverable:
  forall tp msgs, In tp (subscribed m) ->
  last_delivered (sub_of tp) (accepted_in (rcl_deliverable subs_of msgs)) = last_on (tp_name tp) (received_on m tp msgs).
Proof.
  intros tp msgs Htp. assert (Hs: In (sub_of tp) subs_of) by (unfold subs_of; apply in_map; auto).
  assert (Acc: forall a, accepted ge (sub_of tp) a = negb (too_long (composites m) (Tstruct (tp_msg tp)) (ar_msg a)))
    by (intros a; unfold accepted; rewrite globalenv_comp, types_eq; reflexivity).
  assert (Q: (1 <= tp_queue tp)%nat).
  { apply in_subscribed in Htp as [Ht _]. generalize (wf_topics m W tp Ht). unfold topic_ok.
    rewrite !andb_true_iff. intros ((((_ & _) & _) & Q) & _). apply Nat.leb_le. exact Q. }
  rewrite <- last_delivered_of_sub. unfold accepted_in. rewrite filter_comm.
  rewrite (filter_rcl_deliverable subs_of msgs (sub_of tp) subs_of_nodup Hs).
  unfold taken. cbn [sub_topic sub_queue sub_of].
  induction msgs as [|a rest IH]; [reflexivity|].
  cbn [history received_on]. rewrite map_app, filter_app, last_delivered_app, IH, last_on_app.
  destruct (last_on (tp_name tp) (received_on m tp rest)) as [v|]; [reflexivity|].
  replace (Nat.eqb (tp_queue tp) 0) with false by (symmetry; apply Nat.eqb_neq; lia). cbn [orb].
  destruct (topic_eqb (ar_topic a) (tp_name tp) && Nat.ltb (count_topic (tp_name tp) rest) (tp_queue tp)) eqn:C;
    cbn [andb map filter last_delivered app]; [|reflexivity].
  cbn [fst snd]. rewrite Acc.
  destruct (negb (too_long (composites m) (Tstruct (tp_msg tp)) (ar_msg a))); [|reflexivity].
  cbn [last_delivered last_on]. apply andb_true_iff in C as [T _]. unfold topic_eqb in T.
  destruct (string_dec (ar_topic a) (tp_name tp)); [|discriminate].
  destruct (sub_eq (sub_of tp) (sub_of tp)); congruence.
Qed.

Lemma spin_run:
  forall k r s e mm, loop_inv k nonew e mm ->
  exists mm',
     eval_funcall ctx ge mm (wld k r s) (External EF_ros_spinOnce [] Tvoid) [] [] mm' (wld (S k) r s) Vundef
  /\ loop_inv (S k) (arrived_at k) e mm'.
Proof.
  intros k r s e mm I.
  set (D := spin_messages ctx (wld k r s)).
  destruct (deliver_run D (wld k r s) mm (fun tp => held m ctx tp k) (fun tp => (false, held_time tp k))
              (li_wf I) (li_globals I) (li_msgs I) (li_direct I) (li_clock I))
    as (mm' & w' & X & NS & W' & GT' & HG' & HU' & HC' & Fr').
  { intros s0 a H0. apply In_spin_messages in H0. destruct H0 as (Hs & Ha & Et).
    unfold subs_of in Hs. apply in_map_iff in Hs. destruct Hs as (tp & <- & Htp).
    exists tp; repeat split; auto. eapply AWT; eauto. }
  assert (LD: forall tp, In tp (subscribed m) ->
            last_delivered (sub_of tp) (accepted_in D) = last_on (tp_name tp) (received_on m tp (ctx_arrivals ctx k)))
    by (intros tp Htp; unfold D, spin_messages; destruct (ctx_target ctx);
        [apply last_accepted_deliverable|apply last_accepted_rcl_deliverable]; auto).
  exists mm'. split.
  - change (wld (S k) r s) with (next_spin ctx (wld k r s)). rewrite <- NS.
    apply eval_funcall_spinOnce. exact X.
  - constructor; auto.
    + intros tp Htp. destruct (HG' tp Htp) as (g & Gg & Ag). exists g; split; [exact Gg|].
      rewrite LD in Ag by auto. simpl. rewrite newest_step. exact Ag.
    + intros tp Htp. destruct (li_cmds I tp Htp) as (b & F & NG & v & G & S).
      exists b; split; auto; split; auto. exists v; split; auto.
      rewrite Fr'; auto. congruence.
    + intros tp Ht. generalize (HC' tp Ht). rewrite LD by (apply timed_subscribed; auto).
      unfold arrived_at, arrived. cbn [held_time]. rewrite newest_time_step.
      destruct (last_on (tp_name tp) (received_on m tp (ctx_arrivals ctx k))); auto.
    + apply (li_funs I).
    + intros tp ir Htp Hd. rewrite (HU' tp ir Htp Hd), LD by auto. simpl. rewrite newest_step. reflexivity.
Qed.

(** *** [input_glue], [Controller_step], output glue and publication *)

Lemma call0_exec:
  forall e le mm w f fd t mm' w' v,
  find_assoc f e = None -> find_var ge f = None -> find_funct ge f = Some fd ->
  type_of_fundef fd = Tfunction [] Tvoid ->
  eval_funcall ctx ge mm w fd [] t mm' w' v ->
  exec_stmt ctx ge e le mm w (call0 f) t le mm' w' Out_normal.
Proof.
  intros. unfold call0. change le with (set_opttemp None v le) at 2.
  eapply exec_call_named; eauto. reflexivity.
Qed.

(** The clock state of the timed topic with C name [c] after spin [k]. *)
Definition clock_at (k : nat) (c : ident) : bool * option Z :=
  match find_topic (nm_topics m) c with
  | Some tp => (arrived m ctx tp k, newest_time m ctx tp k)
  | None => (false, None)
  end.

Lemma clock_at_topic:
  forall k tp, In tp (subscribed m) -> clock_at k (tp_cname tp) = (arrived m ctx tp k, newest_time m ctx tp k).
Proof.
  intros k tp H. unfold clock_at. rewrite In_find_topic; auto.
  - apply wf_cnames_nodup; auto.
  - apply in_subscribed in H; tauto.
Qed.

Lemma input_run:
  forall k r s e le mm, loop_inv (S k) (arrived_at k) e mm ->
  exists mm' u,
     exec_stmt ctx ge e le mm (wld (S k) r s) (call0 input_glue_name) [] le mm' (wld (S k) r s) Out_normal
  /\ input_values m ctx k u
  /\ global_value p mm' (nm_in_var m) = Some u
  /\ loop_inv (S k) nonew e mm'.
Proof.
  intros k r s e le mm I.
  destruct (generate_input_glue_ddc m p GEN) as (f & Ff & Spec).
  destruct (generate_input_glue m p GEN) as (f' & Fd & Fret & Fpar & _).
  assert (Ef: f' = f) by (rewrite (gen_funct m p GEN _ _ Fd) in Ff; congruence). subst f'.
  assert (CK: forall tp, In tp (timed m) ->
            clock_held p mm (tp_cname tp) (fst (clock_at k (tp_cname tp))) (snd (clock_at k (tp_cname tp)))).
  { intros tp Ht. rewrite clock_at_topic by (apply timed_subscribed; auto). apply (li_clock I tp Ht). }
  destruct (Spec mm (clock_at k) (li_globals I) CK CS ctx (wld (S k) r s)) as [[t [mm' [w' [v X]]]] All].
  destruct (All _ _ _ _ X) as (-> & -> & -> & (u & GC & Tu & Rel & Der & Dir)).
  rewrite types_eq in Tu.
  cbn [w_time wld] in Rel, Der.
  inversion GC as [|? mm1 ? ? ? ? OG GC']; subst.
  exists mm', u. split; [|split; [|split]].
  - eapply call0_exec; eauto.
    + apply (li_funs I). eapply def_name; eauto.
    + eapply fun_not_var; eauto.
    + simpl. unfold type_of_function. rewrite Fpar, Fret. auto.
  - split; [auto|split].
    + intros ir Hir. destruct (is_direct m ir) eqn:D.
      { destruct (input_exprs m ir W Hir) as (tp & t & q & _ & Ec & Hs & _).
        assert (Hd: In ir (direct_of m (tp_cname tp))) by (apply direct_of_In; auto).
        destruct (gen_input_leaf_scalar m p GEN ir u Hir Tu) as (v & Gv).
        exists tp, v. repeat split; auto.
        - change (newest m ctx tp k) with (held m ctx tp (S k)).
          rewrite <- (li_direct I tp ir Hs Hd), <- (Dir ir Hir D). exact Gv.
        - unfold fed_value. rewrite (direct_no_fallback m p GEN ir Hir D).
          destruct (stale _ _ _ _); exact Gv. }
      assert (Hg: In ir (glue_inrels m)) by (apply glue_inrels_In; auto).
      destruct (Rel ir Hg) as (g & v & GV & Gg & Gv).
      destruct (input_exprs m ir W Hir) as (tp & t & q & _ & Ec & Hs & _).
      exists tp, v. repeat split; auto.
      * rewrite <- Ec in GV. destruct (li_msgs I tp Hs) as (g' & Gg' & Ag). rewrite Gg' in GV. inversion GV; subst g'.
        transitivity (mval_get g (path_steps (ir_path ir))); [symmetry; apply Ag|exact Gg].
        rewrite Ec. apply inrel_read; auto.
      * rewrite Gv. rewrite <- Ec, clock_at_topic by auto. reflexivity.
    + intros dr Hdr. destruct (drel_topic m p GEN dr Hdr) as (tp & Ht & Ec & _).
      exists tp. split; [apply timed_subscribed; auto|split; auto].
      rewrite Der by auto. rewrite <- Ec, clock_at_topic by (apply timed_subscribed; auto). reflexivity.
  - rewrite (globals_changed_notin _ _ _ GC').
    + eapply only_global_same; eauto.
    + rewrite map_map. simpl. intros Hx. apply in_map_iff in Hx. destruct Hx as (tp & E & Ht).
      apply (proj1 (controller_not_clock tp _ Ht (or_intror (or_introl eq_refl)))). auto.
  - assert (I1: loop_inv (S k) (arrived_at k) e mm1).
    { apply (inv_change_global_gen (S k) (arrived_at k) (arrived_at k) e mm mm1 (nm_in_var m) u I OG).
      + intros tp Htp E. apply (proj1 (gen_in_out_vars m p GEN tp Htp)); auto.
      + intros _ tp ir Htp Hd. apply direct_of_In in Hd as (Hir & _ & D). apply Dir; auto.
      + intros b ty' V. destruct (generate_externals m p GEN) as (_ & _ & _ & _ & _ & _ & Fu & _).
        destruct (gen_var m p GEN _ _ Fu) as [bu' Vu'].
        rewrite V in Vu'. inversion Vu'; subst. auto.
      + intros tp Ht. apply clock_held_same with mm; [|apply (li_clock I tp Ht)].
        intros y Hy. eapply only_global_other; eauto. apply (proj1 (controller_not_clock tp y Ht Hy)). }
    generalize (inv_resets (S k) (timed m) (arrived_at k) e mm1 mm' (incl_refl _) I1 GC').
    apply loop_inv_ext. intros tp Ht.
    replace (existsb (fun t => ident_eqb (tp_cname t) (tp_cname tp)) (timed m)) with true; auto.
    symmetry. apply existsb_exists. exists tp. split; auto. apply ident_eqb_refl.
Qed.

Lemma step_run:
  forall k r s e le mm u, loop_inv (S k) nonew e mm -> global_value p mm (nm_in_var m) = Some u ->
  exists mm' y s',
     exec_stmt ctx ge e le mm (wld (S k) r s) (call0 (step_name m)) [Estep u y] le mm' (wld (S k) r s') Out_normal
  /\ ctx_step ctx s u = (s', y)
  /\ global_value p mm' (nm_out_var m) = Some y
  /\ loop_inv (S k) nonew e mm'.
Proof.
  intros k r s e le mm u I GU.
  destruct (generate_externals m p GEN) as (_ & _ & _ & _ & _ & Fs & Fu & Fy).
  destruct (gen_var m p GEN _ _ Fu) as [bu Vu]. destruct (gen_var m p GEN _ _ Fy) as [by_ Vy].
  destruct (li_globals I _ _ _ Vy) as (y0 & Gy0 & _).
  unfold global_value in GU. rewrite Vu in GU.
  destruct (get_block mm bu) as [[tu uv]|] eqn:Gu; inversion GU; subst uv.
  destruct (ctx_step ctx s u) as [s' y] eqn:CS1.
  assert (Ty: mval_has_type ce (Tstruct (nm_out_struct m)) y).
  { generalize (CWT s u). rewrite CS1. auto. }
  set (mm' := mkmem (pset by_ (Tstruct (nm_out_struct m), y) (mem_contents mm)) (mem_next mm)).
  assert (St: store_path mm by_ [] y = Some mm') by (unfold store_path; rewrite Gy0; reflexivity).
  assert (G': get_block mm' by_ = Some (Tstruct (nm_out_struct m), y)) by (unfold get_block, mm'; simpl; apply pgss).
  exists mm', y, s'. split; [|split; [auto|split]].
  - eapply call0_exec.
    + apply (li_funs I). eapply def_name; eauto.
    + eapply fun_not_var; eauto.
    + apply (gen_funct m p GEN _ _ Fs).
    + reflexivity.
    + assert (LP: load_path mm bu [] = Some u) by (unfold load_path; rewrite Gu; reflexivity).
      assert (LY: load_path mm by_ [] = Some y0) by (unfold load_path; rewrite Gy0; reflexivity).
      apply eval_funcall_external. simpl. rewrite Vu, Vy, LP, LY.
      replace (mval_typecheck (ge_comp ge) (Tstruct (nm_in_struct m)) u
               && mval_typecheck (ge_comp ge) (Tstruct (nm_out_struct m)) y0) with true.
      2:{ symmetry. rewrite (gen_comp m p GEN). apply andb_true_iff. split; apply mval_typecheck_iff.
          - destruct (li_globals I _ _ _ Vu) as (u0 & Gu0 & Tu0). rewrite Gu in Gu0. inversion Gu0; subst.
            rewrite types_eq in Tu0. exact Tu0.
          - destruct (li_globals I _ _ _ Vy) as (y1 & Gy1 & Ty1). rewrite Gy0 in Gy1. inversion Gy1; subst.
            rewrite types_eq in Ty1. exact Ty1. }
      rewrite CS1.
      replace (mval_typecheck (ge_comp ge) (Tstruct (nm_out_struct m)) y) with true.
      * rewrite St. reflexivity.
      * symmetry. rewrite (gen_comp m p GEN). apply mval_typecheck_iff. auto.
  - unfold global_value. rewrite Vy, G'. auto.
  - apply (inv_change_global (S k) nonew e mm mm' (nm_out_var m) y I).
    + exists by_, (Tstruct (nm_out_struct m)). split; auto. split; auto.
      split; auto. intros b' N. unfold get_block, mm'; simpl. apply pgso; auto.
    + intros tp Htp E. apply (proj2 (gen_in_out_vars m p GEN tp Htp)); auto.
    + intros tp y' Ht Hy. apply (controller_not_clock tp y' Ht Hy).
    + intros E. destruct (wf_controller_vars_fresh m W) as (NUY & _ & _). apply NUY; auto.
    + intros b ty V. rewrite Vy in V. inversion V; subst. auto.
Qed.

Lemma cmd_arg:
  forall e le mm tp b,
  find_assoc (cmd_var (tp_cname tp)) e = Some (b, Tstruct (tp_msg tp)) ->
  eval_exprlist ge e le mm [cmd_addr tp] [tptr (Tstruct (tp_msg tp))] = Some [Vptr b []].
Proof.
  intros e le mm tp b H. unfold cmd_addr. cbn [eval_exprlist eval_expr eval_lvalue].
  unfold lvalue_var. rewrite H. reflexivity.
Qed.

(** Writing a message of its type into the local [c_cmd] of a published
    topic keeps the invariant. *)
Lemma inv_change_cmd:
  forall k nw e mm mm1 tp b mv,
  loop_inv k nw e mm -> In tp (published m) ->
  find_assoc (cmd_var (tp_cname tp)) e = Some (b, Tstruct (tp_msg tp)) ->
  get_block mm1 b = Some (Tstruct (tp_msg tp), mv) ->
  mval_has_type ce (Tstruct (tp_msg tp)) mv ->
  unchanged_except mm mm1 b ->
  loop_inv k nw e mm1.
Proof.
  intros k nw e mm mm1 tp b mv I Htp Fb G1 Tmv [N1 O1].
  destruct (li_cmds I tp Htp) as (b' & Fb' & NG & v & Gb & Sb).
  rewrite Fb in Fb'; inversion Fb'; subst b'.
  constructor.
  - eapply mem_wf_unchanged; [apply (li_wf I) | split; eauto | congruence].
  - intros x bx tx V. rewrite O1 by (apply (NG _ _ _ V)). apply (li_globals I _ _ _ V).
  - intros tp' Htp'. generalize (li_msgs I tp' Htp'). unfold global_value.
    destruct (find_var ge (msg_var (tp_cname tp'))) as [[bg ty]|] eqn:Vg; auto.
    rewrite O1; auto. apply (NG _ _ _ Vg).
  - intros tp2 Htp2. destruct (li_cmds I tp2 Htp2) as (b2 & F2 & NG2 & v2 & G2 & S2).
    exists b2; split; auto; split; auto.
    destruct (Pos.eq_dec b2 b) as [->|Nb].
    + rewrite Gb in G2. injection G2 as EM _. exists mv; split.
      * rewrite G1, EM. auto.
      * rewrite <- EM. apply zero_shape; auto. apply in_published in Htp; tauto.
    + exists v2; split; auto. rewrite O1; auto.
  - intros tp' Ht. apply clock_held_same with mm; [|apply (li_clock I tp' Ht)].
    intros y Hy. apply global_value_same. intros by_ ty V. apply O1. intros ->. apply (NG _ _ _ V); auto.
  - apply (li_funs I).
  - intros tp' ir Htp' Hd. rewrite <- (li_direct I tp' ir Htp' Hd). unfold global_inputs.
    rewrite (global_value_same mm mm1 (nm_in_var m)); [reflexivity|].
    intros by_ ty V. apply O1. intros ->. apply (NG _ _ _ V); auto.
Qed.

(** The published message depends on the held messages only through
    the sources of copied stamps, which are paths that the node reads of
    subscribed topics. *)
Lemma published_value_ext:
  forall g1 g2 y now tp mv,
  (forall tp', In tp' (subscribed m) -> reads_agree tp' (g1 (tp_cname tp')) (g2 (tp_cname tp'))) ->
  published_value m y now g1 tp mv -> published_value m y now g2 tp mv.
Proof.
  intros g1 g2 y now tp mv E (T & R & S & Z). split; [auto|split; [auto|split; [|exact Z]]].
  intros sp F. generalize (S sp F). unfold stamp_nsec. destruct (find_assoc (tp_cname tp) (nm_stamp_from m)) as [[s0 sp']|] eqn:SF; auto.
  assert (Hin: In (tp_cname tp, (s0, sp')) (nm_stamp_from m)) by (apply find_assoc_In; auto).
  destruct (wf_stamp_from m _ _ _ W Hin) as (tp' & Ft & Sub & _).
  destruct (find_topic_In _ _ _ Ft) as [Htop' Ec].
  assert (Hs': In tp' (subscribed m)).
  { apply in_subscribed. split; auto. unfold is_subscribed in Sub. destruct (tp_dir tp'); [auto|discriminate]. }
  destruct (stamp_from_read m _ _ _ Hin) as [Rs Rn]. rewrite <- Ec in Rs, Rn.
  rewrite <- Ec, <- (E tp' Hs' _ Rs), <- (E tp' Hs' _ Rn). auto.
Qed.

Lemma publishes_run:
  forall k r s e y tps le mm, incl tps (published m) ->
  loop_inv (S k) nonew e mm -> global_value p mm (nm_out_var m) = Some y ->
  exists mm' mvs,
     exec_stmt ctx ge e le mm (wld (S k) r s)
       (seq_of (flat_map publish_stmts tps ++ [call0 ros_rate_sleep_name]))
       (publish_events m tps mvs ++ [Esleep (nm_period_ms m)]) le mm' (wld (S k) r s) Out_normal
  /\ Forall2 (published_value m y (ctx_time ctx (S k)) (newest_by m ctx k)) tps mvs
  /\ loop_inv (S k) nonew e mm'.
Proof.
  intros k r s e y tps; induction tps as [|tp tps IH]; intros le mm Inc I GY.
  - exists mm, []. split; [|split; [constructor|auto]].
    destruct (generate_externals m p GEN) as (_ & _ & _ & Frs & _).
    simpl. change [Esleep (nm_period_ms m)] with ([Esleep (nm_period_ms m)] ++ []).
    eapply exec_Sseq_1; [|apply exec_Sskip].
    eapply call0_exec.
    + apply (li_funs I). eapply def_name; eauto.
    + eapply fun_not_var; eauto.
    + apply (gen_funct m p GEN _ _ Frs).
    + reflexivity.
    + apply eval_funcall_external. reflexivity.
  - assert (Htp: In tp (published m)) by (apply Inc; simpl; auto).
    assert (Htop: In tp (nm_topics m)) by (apply in_published in Htp; tauto).
    assert (Pub: tp_dir tp = Publish) by (apply in_published in Htp; tauto).
    destruct (li_cmds I tp Htp) as (b & Fb & NG & v & Gb & Sb).
    destruct (generate_output_glue_ddc m p GEN tp Htp) as (f & Ff & Spec).
    destruct (generate_output_glue m p tp GEN Htp) as (f' & Fd & Fret & Fpar & _).
    assert (Ef: f' = f) by (rewrite (gen_funct m p GEN _ _ Fd) in Ff; congruence). subst f'.
    destruct (Spec mm b v y (li_globals I) NG Gb ltac:(rewrite types_eq; auto) GY CS ctx (wld (S k) r s))
      as [[t [mm1 [w1 [v1 X]]]] All].
    destruct (All _ _ _ _ X) as (-> & -> & -> & (mv & G1 & PV & U1)).
    generalize (generate_topic_externals m p tp GEN Htop). rewrite Pub. intros [_ Fpub].
    assert (I1: loop_inv (S k) nonew e mm1).
    { eapply inv_change_cmd; eauto. apply PV. }
    assert (GY1: global_value p mm1 (nm_out_var m) = Some y).
    { generalize GY. unfold global_value.
      destruct (find_var ge (nm_out_var m)) as [[by_ ty]|] eqn:Vy; auto.
      destruct U1 as [_ O1]. rewrite O1; auto. apply (NG _ _ _ Vy). }
    destruct (IH le mm1) as (mm' & mvs & X' & F' & I'); auto.
    { intros x Hx; apply Inc; simpl; auto. }
    assert (PV': published_value m y (ctx_time ctx (S k)) (newest_by m ctx k) tp mv).
    { apply (published_value_ext (global_msg p mm)); auto.
      intros tp' Hs'. unfold global_msg. destruct (li_msgs I tp' Hs') as (g & Gg & Ag). rewrite Gg.
      unfold newest_by. rewrite In_find_topic; auto.
      - apply wf_cnames_nodup; auto.
      - apply in_subscribed in Hs'; tauto. }
    exists mm', (mv :: mvs). split; [|split; [constructor; auto|auto]].
    change (seq_of (flat_map publish_stmts (tp :: tps) ++ [call0 ros_rate_sleep_name]))
      with (Ssequence (Scall None (Evar (output_glue_name (tp_cname tp)) (callback_type (tp_msg tp))) [cmd_addr tp])
           (Ssequence (Scall None (Evar (publish_name (tp_cname tp)) (callback_type (tp_msg tp))) [cmd_addr tp])
                      (seq_of (flat_map publish_stmts tps ++ [call0 ros_rate_sleep_name])))).
    change (publish_events m (tp :: tps) (mv :: mvs) ++ [Esleep (nm_period_ms m)])
      with ([] ++ ([Epublish (tp_name tp) (sent m tp mv)] ++ (publish_events m tps mvs ++ [Esleep (nm_period_ms m)]))).
    eapply exec_Sseq_1; [|eapply exec_Sseq_1; [|exact X']].
    + unfold callback_type. eapply exec_call_none; eauto.
      * apply (li_funs I). eapply def_name; eauto.
      * eapply fun_not_var; eauto.
      * simpl. unfold type_of_function. rewrite Fpar, Fret. auto.
      * apply cmd_arg; auto.
    + unfold callback_type. eapply exec_call_none.
      * apply (li_funs I). eapply def_name; eauto.
      * eapply fun_not_var; eauto.
      * apply (gen_funct m p GEN _ _ Fpub).
      * reflexivity.
      * apply cmd_arg; exact Fb.
      * apply eval_funcall_external. simpl.
        replace (existsb (topic_eqb (tp_name tp)) advs_of) with true.
        -- unfold load_path. rewrite G1. simpl. unfold sent. rewrite globalenv_comp, types_eq. reflexivity.
        -- symmetry. apply existsb_exists. exists (tp_name tp). split.
           ++ unfold advs_of. apply in_map; auto.
           ++ unfold topic_eqb. destruct (string_dec (tp_name tp) (tp_name tp)); congruence.
Qed.

(** *** One cycle, the loop *)

Definition loop_body : statement :=
  Ssequence (Scall (Some ok_temp) (Evar ros_ok_name (Tfunction [] tint)) [])
 (Ssequence (Sifthenelse (Etempvar ok_temp tint) Sskip Sbreak)
 (Ssequence (call0 ros_spinOnce_name)
 (Ssequence (call0 input_glue_name)
 (Ssequence (call0 (step_name m))
            (seq_of (flat_map publish_stmts (published m) ++ [call0 ros_rate_sleep_name])))))).

Lemma ros_ok_exec:
  forall e le mm k r s res w',
  loop_inv k nonew e mm ->
  external_call ctx ge EF_ros_ok [] mm (wld k r s) = Some (Vint res, [], mm, w') ->
  exec_stmt ctx ge e le mm (wld k r s) (Scall (Some ok_temp) (Evar ros_ok_name (Tfunction [] tint)) [])
            [] (set_assoc ok_temp (Vint res) le) mm w' Out_normal.
Proof.
  intros e le mm k r s res w' I Ex.
  destruct (generate_externals m p GEN) as (_ & Fok & _).
  change (set_assoc ok_temp (Vint res) le) with (set_opttemp (Some ok_temp) (Vint res) le).
  eapply exec_call_named.
  - apply (li_funs I). eapply def_name; eauto.
  - eapply fun_not_var; eauto.
  - apply (gen_funct m p GEN _ _ Fok).
  - reflexivity.
  - reflexivity.
  - apply eval_funcall_external. exact Ex.
Qed.

Lemma cycle_run:
  forall k r s e le mm, loop_inv k nonew e mm ->
  exists evs le' mm' s',
     exec_stmt ctx ge e le mm (wld k (S r) s) loop_body evs le' mm' (wld (S k) r s') Out_normal
  /\ cycle_ok m ctx k s evs s'
  /\ loop_inv (S k) nonew e mm'.
Proof.
  intros k r s e le mm I.
  set (le1 := set_assoc ok_temp (Vint 1) le).
  destruct (generate_externals m p GEN) as (_ & _ & Fspin & _).
  destruct (spin_run k r s e mm I) as (mm2 & Xs & I2).
  destruct (input_run k r s e le1 mm2 I2) as (mm3 & u & Xi & IV & GU & I3).
  destruct (step_run k r s e le1 mm3 u I3 GU) as (mm4 & y & s' & Xst & CSt & GY & I4).
  destruct (publishes_run k r s' e y (published m) le1 mm4 (incl_refl _) I4 GY)
    as (mm5 & mvs & Xp & PV & I5).
  exists (Estep u y :: publish_events m (published m) mvs ++ [Esleep (nm_period_ms m)]), le1, mm5, s'.
  split; [|split; [exists u, y, mvs; auto|auto]].
  unfold loop_body.
  change (Estep u y :: publish_events m (published m) mvs ++ [Esleep (nm_period_ms m)])
    with ([] ++ ([] ++ ([] ++ ([] ++ ([Estep u y] ++ (publish_events m (published m) mvs
                                                     ++ [Esleep (nm_period_ms m)])))))).
  eapply exec_Sseq_1.
  { apply ros_ok_exec; auto. reflexivity. }
  eapply exec_Sseq_1.
  { eapply exec_Sifthenelse.
    - simpl. unfold le1. apply find_assoc_set_same.
    - reflexivity.
    - apply exec_Sskip. }
  eapply exec_Sseq_1.
  { eapply call0_exec.
    - apply (li_funs I). eapply def_name; eauto.
    - eapply fun_not_var; eauto.
    - apply (gen_funct m p GEN _ _ Fspin).
    - reflexivity.
    - exact Xs. }
  eapply exec_Sseq_1; [exact Xi|].
  eapply exec_Sseq_1; [exact Xst|].
  exact Xp.
Qed.

Lemma loop_run:
  forall r k s e le mm, loop_inv k nonew e mm ->
  exists t le' mm' w',
     exec_stmt ctx ge e le mm (wld k r s) (Sloop loop_body) t le' mm' w' Out_normal
  /\ cycles_ok m ctx k r s t.
Proof.
  induction r as [|r IH]; intros k s e le mm I.
  - exists [], (set_assoc ok_temp (Vint 0) le), mm, (wld k 0 s). split; [|constructor].
    change Out_normal with (loop_outcome Out_break). apply exec_Sloop_stop; [|discriminate].
    unfold loop_body. change (@nil event) with (@nil event ++ @nil event). eapply exec_Sseq_1.
    + apply ros_ok_exec; auto. reflexivity.
    + apply exec_Sseq_2; [|discriminate].
      eapply exec_Sifthenelse.
      * simpl. apply find_assoc_set_same.
      * reflexivity.
      * apply exec_Sbreak.
  - destruct (cycle_run k r s e le mm I) as (evs & le1 & mm1 & s' & X & C & I1).
    destruct (IH (S k) s' e le1 mm1 I1) as (t & le' & mm' & w' & X' & C').
    exists (evs ++ t), le', mm', w'. split.
    + eapply exec_Sloop_loop; eauto.
    + econstructor; eauto.
Qed.

(** *** [main] *)

Lemma complete_struct:
  forall id, In id (md_names (nm_msgs m)) \/ id = nm_in_struct m \/ id = nm_out_struct m ->
  complete_type (composite_names ce) (Tstruct id) = true.
Proof.
  intros id H. simpl. apply in_ident_spec. unfold composite_names, composites.
  rewrite map_app, map_map. simpl. apply in_or_app.
  destruct H as [H|[H|H]]; [left; exact H | right; left; auto | right; right; left; auto].
Qed.

(** The global variables of the program have struct types of the model. *)
Lemma global_var_types:
  forall x b ty, find_var ge x = Some (b, ty) -> complete_type (composite_names ce) ty = true.
Proof.
  intros x b ty V. apply find_var_globalenv in V; auto.
  apply (find_def_build m p x _ GEN) in V.
  unfold build_defs in V. rewrite !in_app_iff in V.
  destruct V as [V|[V|[V|[V|[V|[V|[V|[V|V]]]]]]]].
  - unfold ros_externals, time_externals, now_externals, stamp_externals in V.
    destruct (timed m), (nm_stamps m); simpl in V; intuition discriminate.
  - apply in_flat_map in V; destruct V as (tp & _ & V).
    unfold topic_externals in V; destruct (tp_dir tp); simpl in V; intuition discriminate.
  - simpl in V. destruct V as [V|[V|[V|[V|[]]]]]; inversion V; subst; apply complete_struct; auto.
  - apply in_map_iff in V. destruct V as (tp & E & Htp). inversion E; subst.
    apply complete_struct. left. apply (gen_msg_in m p GEN). apply in_subscribed in Htp; tauto.
  - apply in_flat_map in V. destruct V as (tp & _ & V). simpl in V.
    destruct V as [V|[V|[V|[]]]]; inversion V; subst; reflexivity.
  - apply in_map_iff in V; destruct V as (tp & E & _); discriminate.
  - simpl in V; destruct V as [V|[]]; discriminate.
  - apply in_map_iff in V; destruct V as (tp & E & _); discriminate.
  - simpl in V; destruct V as [V|[V|[]]]; discriminate.
Qed.

(** The invariant holds when the loop starts. *)
Lemma loop_entry:
  forall f_loop e m1,
  fn_vars f_loop = map (fun tp => (cmd_var (tp_cname tp), Tstruct (tp_msg tp))) (published m) ->
  NoDup (map fst (fn_vars f_loop)) ->
  alloc_vars ce [] (init_mem p) (fn_vars f_loop) = (e, m1) ->
  loop_inv O nonew e m1.
Proof.
  intros f_loop e m1 Vl NDl AV.
  destruct (alloc_vars_spec ce _ _ _ _ _ AV (init_mem_wf p) NDl) as (W1 & Le & Old & New & Oth).
  assert (GI: forall x b ty, find_var ge x = Some (b, ty) ->
                get_block m1 b = Some (ty, zero_mval ce ty) /\ Pos.lt b (mem_next (init_mem p))).
  { intros x b ty V. destruct (init_mem_global p x b ty V) as [G L].
    rewrite types_eq in G. split; auto. rewrite Old; auto. }
  constructor; auto.
  - intros x b ty V. destruct (GI x b ty V) as [G _]. exists (zero_mval ce ty). split; auto.
    rewrite types_eq. apply zero_mval_has_type; [apply wf_composites_of; auto|].
    eapply global_var_types; eauto.
  - intros tp Htp. destruct (msg_global tp Htp) as [bg Vg]. destruct (GI _ _ _ Vg) as [G _].
    unfold global_value. rewrite Vg, G. eexists; split; [reflexivity|]. intros lp _; auto.
  - intros tp Htp. destruct (New (cmd_var (tp_cname tp)) (Tstruct (tp_msg tp))) as (b & F & Lb & G).
    { rewrite Vl. apply (in_map (fun tp => (cmd_var (tp_cname tp), Tstruct (tp_msg tp)))); auto. }
    exists b. split; auto. split.
    + intros x bx tx V E. subst bx. destruct (GI _ _ _ V) as [_ L]. lia.
    + exists (undef_mval ce (Tstruct (tp_msg tp))). split; [rewrite G; auto|apply shape_undef_mval].
  - intros tp Ht. destruct (generate_clock_globals m p tp GEN Ht) as (Ft & Fn & Fr).
    destruct (gen_var m p GEN _ _ Ft) as [bt Vt]. destruct (gen_var m p GEN _ _ Fn) as [bn Vn].
    destruct (gen_var m p GEN _ _ Fr) as [br Vr].
    destruct (GI _ _ _ Vn) as [Gn _]. destruct (GI _ _ _ Vr) as [Gr _].
    split; [|split].
    + unfold global_value. rewrite Vn, Gn. reflexivity.
    + unfold global_value. rewrite Vr, Gr. reflexivity.
    + intros t E. discriminate.
  - intros x Hx. rewrite Oth; auto. intros Hv. rewrite Vl, map_map in Hv. simpl in Hv.
    apply in_map_iff in Hv. destruct Hv as (tp & Ex & Htp).
    apply (generate_locals_fresh m p x GEN); auto.
    unfold local_names. rewrite !in_app_iff. right; right. subst x. apply in_map_iff; eauto.
  - intros tp ir Htp Hd. destruct (generate_externals m p GEN) as (_ & _ & _ & _ & _ & _ & Fu & _).
    destruct (gen_var m p GEN _ _ Fu) as [bu Vu]. destruct (GI _ _ _ Vu) as [Gu _].
    unfold global_inputs, global_value. rewrite Vu, Gu. cbn [held].
    exact (gen_zero_direct m p GEN tp ir Htp Hd).
Qed.

Lemma subs_run:
  forall tps l le mm s0 n, incl tps (subscribed m) ->
  exec_stmt ctx ge [] le mm (mkworld l [] O n s0 (ctx_time ctx O)) (seq_of (map subscribe_stmt tps))
            (map subscribe_event tps) le mm
            (mkworld (l ++ map sub_of tps) [] O n s0 (ctx_time ctx O)) Out_normal.
Proof.
  induction tps as [|tp tps IH]; intros l le mm s0 n Inc.
  - simpl. rewrite app_nil_r. apply exec_Sskip.
  - assert (Htp: In tp (subscribed m)) by (apply Inc; simpl; auto).
    assert (Htop: In tp (nm_topics m)) by (apply in_subscribed in Htp; tauto).
    assert (Sub: tp_dir tp = Subscribe) by (apply in_subscribed in Htp; tauto).
    generalize (generate_topic_externals m p tp GEN Htop). rewrite Sub. intros Fs.
    destruct (generate_callback m p tp GEN Htp) as [_ (f & Fcb & _)].
    simpl map.
    change (l ++ sub_of tp :: map sub_of tps) with (l ++ [sub_of tp] ++ map sub_of tps).
    change (subscribe_event tp :: map subscribe_event tps)
      with ([subscribe_event tp] ++ map subscribe_event tps).
    rewrite app_assoc. simpl seq_of.
    apply exec_Sseq_1 with (le1 := le) (m1 := mm) (w1 := mkworld (l ++ [sub_of tp]) [] O n s0 (ctx_time ctx O)).
    + unfold subscribe_stmt. eapply exec_call_none.
      * reflexivity.
      * eapply fun_not_var; eauto.
      * apply (gen_funct m p GEN _ _ Fs).
      * reflexivity.
      * unfold callback_type. cbn [eval_exprlist eval_expr]. unfold eval_funcname.
        rewrite (fun_not_var _ _ Fcb), (gen_funct m p GEN _ _ Fcb). reflexivity.
      * apply eval_funcall_external. reflexivity.
    + apply IH. intros x Hx; apply Inc; simpl; auto.
Qed.

Lemma advs_run:
  forall tps l l' le mm s0 n, incl tps (published m) ->
  exec_stmt ctx ge [] le mm (mkworld l l' O n s0 (ctx_time ctx O)) (seq_of (map advertise_stmt tps))
            (map advertise_event tps) le mm
            (mkworld l (l' ++ map tp_name tps) O n s0 (ctx_time ctx O)) Out_normal.
Proof.
  induction tps as [|tp tps IH]; intros l l' le mm s0 n Inc.
  - simpl. rewrite app_nil_r. apply exec_Sskip.
  - assert (Htp: In tp (published m)) by (apply Inc; simpl; auto).
    assert (Htop: In tp (nm_topics m)) by (apply in_published in Htp; tauto).
    assert (Pub: tp_dir tp = Publish) by (apply in_published in Htp; tauto).
    generalize (generate_topic_externals m p tp GEN Htop). rewrite Pub. intros [Fa _].
    simpl map.
    change (l' ++ tp_name tp :: map tp_name tps) with (l' ++ [tp_name tp] ++ map tp_name tps).
    change (advertise_event tp :: map advertise_event tps)
      with ([advertise_event tp] ++ map advertise_event tps).
    rewrite app_assoc. simpl seq_of.
    apply exec_Sseq_1 with (le1 := le) (m1 := mm) (w1 := mkworld l (l' ++ [tp_name tp]) O n s0 (ctx_time ctx O)).
    + unfold advertise_stmt. eapply call0_exec.
      * reflexivity.
      * eapply fun_not_var; eauto.
      * apply (gen_funct m p GEN _ _ Fa).
      * reflexivity.
      * apply eval_funcall_external. reflexivity.
    + apply IH. intros x Hx; apply Inc; simpl; auto.
Qed.

(** [main] runs to completion, and its trace is a run of [n] correct
    cycles. *)
Lemma main_run:
  forall n, exists t, program_behaves p ctx n t /\ run_ok m ctx n t.
Proof.
  intros n.
  destruct (generate_main m p GEN) as (Pm & fm & Fm & Rm & Pm' & Vm & Tm & Bm).
  destruct (generate_loop m p GEN) as (fl & Fl & Rl & Pl & Vl & NDl & Tl & Bl).
  destruct (generate_externals m p GEN) as (Fi & _ & _ & _ & Fci & _).
  destruct (alloc_vars ce [] (init_mem p) (fn_vars fl)) as [e m1] eqn:AV.
  assert (I0: loop_inv O nonew e m1) by (eapply loop_entry; eauto).
  destruct (loop_run n O (ctx_init ctx) e [(ok_temp, Vundef)] m1 I0) as (t & le' & mm' & w' & X & C).
  exists (start_events m ++ t). split; [|apply run_ok_of_cycles; auto].
  econstructor.
  - rewrite Pm. apply (gen_funct m p GEN _ _ Fm).
  - eapply eval_funcall_internal.
    + unfold function_entry. rewrite Vm, Pm', Tm. reflexivity.
    + rewrite Bm.
      replace (start_events m ++ t)
        with ([Einit] ++ (map subscribe_event (subscribed m) ++ (map advertise_event (published m)
              ++ (t ++ []))))
        by (unfold start_events; simpl; rewrite app_nil_r, app_assoc; reflexivity).
      eapply exec_seq_of_app.
      { eapply exec_seq_cons.
        - eapply call0_exec; [reflexivity | eapply fun_not_var; eauto | apply (gen_funct m p GEN _ _ Fi)
                             | reflexivity | apply eval_funcall_external; reflexivity].
        - simpl seq_of. change [Einit] with ([Einit] ++ []). eapply exec_Sseq_1; [|apply exec_Sskip].
          eapply call0_exec; [reflexivity | eapply fun_not_var; eauto | apply (gen_funct m p GEN _ _ Fci)
                             | reflexivity | apply eval_funcall_external; reflexivity]. }
      eapply exec_seq_of_app.
      { apply (subs_run (subscribed m) [] [] (init_mem p) (Some (ctx_init ctx)) n (incl_refl _)). }
      eapply exec_seq_of_app.
      { apply (advs_run (published m) _ [] [] (init_mem p) (Some (ctx_init ctx)) n (incl_refl _)). }
      simpl seq_of. eapply exec_Sseq_1.
      * eapply call0_exec; [reflexivity | eapply fun_not_var; eauto | apply (gen_funct m p GEN _ _ Fl)
                           | simpl; unfold type_of_function; rewrite Pl, Rl; reflexivity |].
        change (wld O n (ctx_init ctx)) with
          (mkworld ([] ++ map sub_of (subscribed m)) ([] ++ map tp_name (published m)) O n
                   (Some (ctx_init ctx)) (ctx_time ctx O)) in X.
        eapply eval_funcall_internal.
        -- unfold function_entry. rewrite (gen_comp m p GEN), AV, Pl, Tl. reflexivity.
        -- rewrite Bl. exact X.
        -- rewrite Rl. reflexivity.
      * apply exec_Sseq_2; [apply exec_Sreturn_some; reflexivity | discriminate].
    + rewrite Rm. reflexivity.
Qed.

End NODE.

(** ** The theorem *)

(** Data delivery correctness of every generated node (theorem T2).

    What it means for a robot: take any node model that pyrosgen accepts
    and the program it generates.  Put the node in any environment:
    sensor messages arrive at any times and in any order on any topics
    (each of the right type), and the controller is any function with
    outputs of the right type.  Let [ros_ok] allow [n] cycles.  Then the
    node first initialises the controller, subscribes to exactly the
    model's subscribed topics (names, message types, queue sizes, in
    model order) and advertises exactly its published topics (likewise);
    then it runs exactly [n] cycles and stops, and in every cycle [i]: the
    controller is called once, and each of its inputs is the field that
    the model relates to it, of the newest message received on that
    topic up to this cycle (zero if none has arrived yet), even when
    older messages were dropped by the queues; then every published
    topic, in model order, publishes one message whose related fields
    are the controller's outputs of this very step and whose other
    fields are zero; then it sleeps with the model's period.  Nothing
    else is observable.  This is the paper's DDC property plus its
    preservation property, over whole runs. *)
Theorem generate_node_ddc:
  forall m p, generate m = OK p -> node_ddc m p.
Proof.
  intros m p GEN CS ctx n AWT CWT.
  destruct (main_run m p GEN ctx AWT CWT n) as (t & B & R).
  split; [eauto|].
  intros t' B'. rewrite (program_behaves_determ CS p ctx n t' t B' B). auto.
Qed.
