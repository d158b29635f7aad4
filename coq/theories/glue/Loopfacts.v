(** * Facts for the proof of the generated node (theorem T2) *)

(** What the proof of T2 ([Loopproof]) uses and that does not depend on
    one generated program: arrivals and queues (the newest message of a
    topic, [last_delivered_deliverable]: a queue keeps the newest
    message), sequences of statements and calls, the allocation of the
    locals, whole runs built from cycles ([cycles_ok], [run_ok_of_cycles]),
    the subscription of a topic ([sub_of]), facts on lists without
    duplicates and on memories. *)

From Coq Require Import String List ZArith Bool Lia.
From ROSGen Require Import Errors Maps Syntax Values Memory Environment Semantics NodeModel Wellformed Generator Generatorspec Generatorproof.
From ROSGen Require Import DDC Copyproof Glueproof.
Import ListNotations.

Local Open Scope list_scope.

(** ** Arrivals and queues *)


(** The message held after cycle [k]: the newest one of the first [k]
    spins (zero before the first). *)
Definition held {CS : Type} (m : node_model) (ctx : ros_context CS) (tp : topic) (k : nat) : mval :=
  match k with
  | O => zero_mval (composites m) (Tstruct (tp_msg tp))
  | S i => newest m ctx tp i
  end.

Lemma newest_step:
  forall CS m (ctx : ros_context CS) tp k,
  newest m ctx tp k
  = match last_on (tp_name tp) (received_on m tp (ctx_arrivals ctx k)) with
    | Some a => converted m tp a
    | None => held m ctx tp k
    end.
Proof.
  intros CS m ctx tp k. unfold newest, newest_arrival.
  rewrite seq_S, flat_map_app. simpl. rewrite app_nil_r, last_on_app.
  destruct (last_on (tp_name tp) (received_on m tp (ctx_arrivals ctx k))); auto.
  destruct k as [|i]; simpl; auto.
Qed.

Definition sub_eq (a b : subscription) : {a = b} + {a <> b}.
Proof. decide equality; first [apply string_dec | apply Nat.eq_dec]. Defined.

(** The last message delivered to subscription [s] in [D]. *)
Fixpoint last_delivered (s : subscription) (D : list (subscription * arrival)) : option arrival :=
  match D with
  | [] => None
  | (s', mv) :: rest =>
      match last_delivered s rest with
      | Some v => Some v
      | None => if sub_eq s' s then Some mv else None
      end
  end.

Lemma last_delivered_app:
  forall s D1 D2,
  last_delivered s (D1 ++ D2)
  = match last_delivered s D2 with Some v => Some v | None => last_delivered s D1 end.
Proof.
  induction D1 as [|[s' mv] D1 IH]; intros D2; simpl.
  - destruct (last_delivered s D2); auto.
  - rewrite IH. destruct (last_delivered s D2); auto.
Qed.

Lemma last_delivered_map:
  forall s mv L,
  last_delivered s (map (fun s' => (s', mv)) L) = if in_dec sub_eq s L then Some mv else None.
Proof.
  induction L as [|s' L IH]; simpl; auto.
  rewrite IH. destruct (in_dec sub_eq s L) as [H|H]; destruct (sub_eq s' s) as [E|E];
    destruct (in_dec sub_eq s (s' :: L)) as [H'|H']; simpl in H'; intuition congruence.
Qed.

Lemma last_delivered_filter_map:
  forall s a L (P : subscription * arrival -> bool),
  last_delivered s (filter P (map (fun s' => (s', a)) L))
  = if in_dec sub_eq s L then (if P (s, a) then Some a else None) else None.
Proof.
  induction L as [|s' L IH]; intros P; simpl; auto.
  destruct (P (s', a)) eqn:Ps'; simpl; rewrite IH;
    destruct (in_dec sub_eq s L) as [H|H]; destruct (sub_eq s' s) as [E|E];
    destruct (in_dec sub_eq s (s' :: L)) as [H'|H']; simpl in H'; subst; try rewrite Ps';
    destruct (P (s, a)); intuition congruence.
Qed.

(** A queue of size at least 1 keeps the newest message: the last
    delivery to a subscription in one spin is the last arrival on its
    topic. *)
Theorem last_delivered_deliverable:
  forall subs s msgs, In s subs -> (1 <= sub_queue s)%nat ->
  last_delivered s (deliverable subs msgs) = last_on (sub_topic s) msgs.
Proof.
  intros subs s msgs Hs Hq. induction msgs as [|[tpn mv tm] rest IH]; simpl; auto.
  rewrite last_delivered_app, IH.
  destruct (last_on (sub_topic s) rest) as [v|] eqn:L; auto.
  rewrite last_delivered_map.
  apply last_on_none_count in L.
  destruct (in_dec sub_eq s _) as [H|H].
  - apply filter_In in H. destruct H as [_ H]. apply andb_true_iff in H. destruct H as [H _].
    unfold topic_eqb in H. destruct (string_dec (sub_topic s) tpn); try discriminate.
    subst. destruct (string_dec (sub_topic s) (sub_topic s)); congruence.
  - destruct (string_dec tpn (sub_topic s)) as [E|E]; auto.
    exfalso. apply H. apply filter_In. split; auto.
    subst tpn. rewrite L. unfold topic_eqb, keeps.
    destruct (string_dec (sub_topic s) (sub_topic s)); [|congruence].
    simpl. apply orb_true_iff; right. apply Nat.ltb_lt. lia.
Qed.

Lemma In_deliverable:
  forall subs msgs s a, In (s, a) (deliverable subs msgs) ->
  In s subs /\ In a msgs /\ ar_topic a = sub_topic s.
Proof.
  induction msgs as [|a' rest IH]; simpl; intros s a H; [contradiction|].
  apply in_app_iff in H. destruct H as [H|H].
  - apply in_map_iff in H. destruct H as (s' & E & H). inversion E; subst.
    apply filter_In in H. destruct H as [Hs H]. apply andb_true_iff in H. destruct H as [H _].
    unfold topic_eqb in H. destruct (string_dec (sub_topic s) (ar_topic a)); try discriminate. auto.
  - destruct (IH _ _ H) as (? & ? & ?); auto.
Qed.

(** *** ROS 2: [rcl_deliverable] *)

(** The two facts the proof of T2 needs of a spin's deliveries
    ([In_deliverable], [last_delivered_deliverable] through
    [Loopproof.last_accepted_deliverable]) hold of ROS 2's too: each
    subscription's messages in take order, one subscription after the
    other, and the subscriptions are distinct. *)

Lemma In_history:
  forall tn q msgs a, In a (history tn q msgs) -> In a msgs /\ ar_topic a = tn.
Proof.
  induction msgs as [|a' rest IH]; simpl; intros a H; [contradiction|].
  apply in_app_iff in H. destruct H as [H|H].
  - destruct (topic_eqb (ar_topic a') tn && _) eqn:C; [|contradiction].
    destruct H as [<-|[]]. apply andb_true_iff in C as [T _]. unfold topic_eqb in T.
    destruct (string_dec (ar_topic a') tn); [auto|discriminate].
  - destruct (IH _ H); auto.
Qed.

Lemma In_rcl_deliverable:
  forall subs msgs s a, In (s, a) (rcl_deliverable subs msgs) ->
  In s subs /\ In a msgs /\ ar_topic a = sub_topic s.
Proof.
  intros subs msgs s a H. unfold rcl_deliverable in H. apply in_flat_map in H as (s0 & Hs0 & H).
  unfold taken in H. apply in_map_iff in H as (a' & E & H). inversion E; subst.
  apply In_history in H. tauto.
Qed.

(** What one spin delivers, on either target, is for registered
    subscriptions and messages of their topics. *)
Lemma In_spin_messages:
  forall CS (ctx : ros_context CS) w s a, In (s, a) (spin_messages ctx w) ->
  In s (w_subs w) /\ In a (ctx_arrivals ctx (w_spins w)) /\ ar_topic a = sub_topic s.
Proof.
  intros CS ctx w s a. unfold spin_messages. destruct (ctx_target ctx).
  - apply In_deliverable.
  - apply In_rcl_deliverable.
Qed.

Definition of_sub (s : subscription) (x : subscription * arrival) : bool :=
  if sub_eq (fst x) s then true else false.

(** The deliveries of one ROS 2 spin to one of distinct subscriptions are
    what it takes from its history, in take order. *)
Lemma filter_none:
  forall (A : Type) (P : A -> bool) l, (forall x, In x l -> P x = false) -> filter P l = [].
Proof.
  induction l as [|x l IH]; intros H; [reflexivity|]. simpl. rewrite (H x (or_introl eq_refl)).
  apply IH. intros y Hy. apply H. right. exact Hy.
Qed.

Lemma filter_rcl_deliverable:
  forall subs msgs s, NoDup subs -> In s subs ->
  filter (of_sub s) (rcl_deliverable subs msgs) = taken s msgs.
Proof.
  induction subs as [|s0 subs IH]; intros msgs s N Hs; [contradiction|].
  apply NoDup_cons_iff in N as [Hn N'].
  assert (Tk: forall s', filter (of_sub s') (taken s' msgs) = taken s' msgs).
  { intros s'. unfold taken. induction (history (sub_topic s') (sub_queue s') msgs) as [|a l IHl]; auto.
    simpl. rewrite IHl. unfold of_sub. simpl. destruct (sub_eq s' s'); congruence. }
  unfold rcl_deliverable. cbn [flat_map]. fold (rcl_deliverable subs msgs).
  rewrite filter_app. destruct Hs as [<-|Hs].
  - rewrite Tk, filter_none, app_nil_r; [reflexivity|].
    intros [s' a] Hx. apply In_rcl_deliverable in Hx as (Hs' & _).
    unfold of_sub. simpl. destruct (sub_eq s' s0); auto. subst; contradiction.
  - rewrite filter_none; [apply IH; auto|].
    intros [s' a] Hx. unfold taken in Hx. apply in_map_iff in Hx as (a' & E & _).
    injection E as <- <-. unfold of_sub. simpl. destruct (sub_eq s0 s) as [E'|]; [subst; contradiction|reflexivity].
Qed.

Lemma last_delivered_of_sub:
  forall s D, last_delivered s (filter (of_sub s) D) = last_delivered s D.
Proof.
  induction D as [|[s' a] D IH]; [reflexivity|].
  cbn [filter]. unfold of_sub at 1. cbn [fst]. destruct (sub_eq s' s) as [E|E].
  - cbn [last_delivered]. rewrite IH. reflexivity.
  - rewrite IH. cbn [last_delivered]. destruct (last_delivered s D); auto. destruct (sub_eq s' s); congruence.
Qed.

Lemma filter_comm:
  forall (A : Type) (P Q : A -> bool) l, filter P (filter Q l) = filter Q (filter P l).
Proof.
  induction l as [|x l IH]; auto. simpl.
  destruct (Q x) eqn:Qx, (P x) eqn:Px; simpl; rewrite ?Qx, ?Px, IH; auto.
Qed.

(** A history of depth at least 1 keeps the newest message: the last
    delivery to a subscription in one ROS 2 spin is the last arrival on
    its topic, as on ROS 1 ([last_delivered_deliverable]). *)
Theorem last_delivered_rcl_deliverable:
  forall subs s msgs, NoDup subs -> In s subs -> (1 <= sub_queue s)%nat ->
  last_delivered s (rcl_deliverable subs msgs) = last_on (sub_topic s) msgs.
Proof.
  intros subs s msgs N Hs Hq. rewrite <- last_delivered_of_sub, filter_rcl_deliverable by auto.
  unfold taken. induction msgs as [|a rest IH]; [reflexivity|].
  cbn [history last_on]. rewrite map_app, last_delivered_app, IH.
  destruct (last_on (sub_topic s) rest) as [v|] eqn:L; [reflexivity|].
  apply last_on_none_count in L. rewrite L. unfold topic_eqb.
  replace (Nat.ltb 0 (sub_queue s)) with true by (symmetry; apply Nat.ltb_lt; lia).
  destruct (string_dec (ar_topic a) (sub_topic s)); cbn; [|reflexivity].
  destruct (sub_eq s s); congruence.
Qed.

(** ** Sequences *)

Section SEQ.

Context {CS : Type}.
Variable ctx : ros_context CS.
Variable ge : genv.

(** Calling a function by its name, from a scope where no local hides it. *)
Lemma exec_call_named:
  forall e le mm w optid f targs tres al fd vargs t mm' w' vres,
  find_assoc f e = None -> find_var ge f = None -> find_funct ge f = Some fd ->
  type_of_fundef fd = Tfunction targs tres ->
  eval_exprlist ge e le mm al targs = Some vargs ->
  eval_funcall ctx ge mm w fd vargs t mm' w' vres ->
  exec_stmt ctx ge e le mm w (Scall optid (Evar f (Tfunction targs tres)) al)
            t (set_opttemp optid vres le) mm' w' Out_normal.
Proof.
  intros. eapply exec_Scall; eauto.
  - cbn [eval_expr]. unfold eval_funcname. rewrite H, H0, H1. auto.
  - reflexivity.
Qed.

Lemma exec_call_none:
  forall e le mm w f targs tres al fd vargs t mm' w' vres,
  find_assoc f e = None -> find_var ge f = None -> find_funct ge f = Some fd ->
  type_of_fundef fd = Tfunction targs tres ->
  eval_exprlist ge e le mm al targs = Some vargs ->
  eval_funcall ctx ge mm w fd vargs t mm' w' vres ->
  exec_stmt ctx ge e le mm w (Scall None (Evar f (Tfunction targs tres)) al) t le mm' w' Out_normal.
Proof.
  intros. change le with (set_opttemp None vres le) at 2. eapply exec_call_named; eauto.
Qed.

End SEQ.

(** ** Allocation of the locals *)

Lemma alloc_vars_spec:
  forall ce vars e mm e' mm',
  alloc_vars ce e mm vars = (e', mm') -> mem_wf mm -> NoDup (map fst vars) ->
     mem_wf mm'
  /\ (Pos.le (mem_next mm) (mem_next mm'))
  /\ (forall b, Pos.lt b (mem_next mm) -> get_block mm' b = get_block mm b)
  /\ (forall x ty, In (x, ty) vars -> exists b, find_assoc x e' = Some (b, ty)
        /\ Pos.le (mem_next mm) b /\ get_block mm' b = Some (ty, undef_mval ce ty))
  /\ (forall x, ~ In x (map fst vars) -> find_assoc x e' = find_assoc x e).
Proof.
  induction vars as [|[x ty] vars IH]; intros e mm e' mm'; cbn [alloc_vars].
  - intros A W ND. inversion A; subst. repeat split; auto; try lia. intros ? ? [].
  - destruct (alloc mm ty (undef_mval ce ty)) as [m1 b] eqn:AL. intros A W ND.
    inversion ND as [|? ? Hx ND']; subst.
    assert (W1: mem_wf m1) by (eapply mem_wf_alloc; eauto).
    destruct (IH _ _ _ _ A W1 ND') as (W2 & Le2 & Old2 & New2 & Oth2).
    assert (Eb: b = mem_next mm) by (eapply alloc_result; eauto).
    assert (En: mem_next m1 = Pos.succ (mem_next mm)) by (eapply alloc_next; eauto).
    repeat split; auto.
    + lia.
    + intros b' Hb'. rewrite Old2 by lia. eapply get_block_alloc_other; eauto. lia.
    + intros x' ty' [E|Hin].
      * inversion E; subst x' ty'. exists b. split; [|split].
        -- rewrite Oth2 by auto. apply find_assoc_set_same.
        -- lia.
        -- rewrite Old2 by lia. eapply get_block_alloc_same; eauto.
      * destruct (New2 x' ty' Hin) as (b' & F & L & G). exists b'. repeat split; auto. lia.
    + intros x' Hx'. simpl in Hx'. rewrite Oth2 by tauto.
      apply find_assoc_set_other. intuition.
Qed.

(** ** Whole runs from cycles *)

Section CYCLES.

Context {CS : Type}.
Variable m : node_model.
Variable ctx : ros_context CS.

(** [cycles_ok k r s t]: [t] is the trace of [r] correct cycles starting
    with cycle [k] in controller state [s]. *)
Inductive cycles_ok : nat -> nat -> CS -> trace -> Prop :=
  | cycles_nil: forall k s, cycles_ok k O s []
  | cycles_cons: forall k r s evs s' t,
      cycle_ok m ctx k s evs s' -> cycles_ok (S k) r s' t -> cycles_ok k (S r) s (evs ++ t).

Lemma cycles_ok_fun:
  forall k r s t, cycles_ok k r s t ->
  exists (sf : nat -> CS) (evf : nat -> trace),
     sf k = s
  /\ t = concat (map evf (seq k r))
  /\ forall i, (k <= i < k + r)%nat -> cycle_ok m ctx i (sf i) (evf i) (sf (S i)).
Proof.
  induction 1 as [k s|k r s evs s' t C _ IH].
  - exists (fun _ => s), (fun _ => []). repeat split; auto. intros; lia.
  - destruct IH as (sf & evf & E0 & Et & Hc).
    exists (fun i => if Nat.eqb i k then s else sf i), (fun i => if Nat.eqb i k then evs else evf i).
    repeat split.
    + rewrite Nat.eqb_refl; auto.
    + simpl. rewrite Nat.eqb_refl. f_equal. rewrite Et. f_equal.
      apply map_ext_in. intros i Hi. apply in_seq in Hi.
      destruct (Nat.eqb i k) eqn:E; auto. apply Nat.eqb_eq in E. lia.
    + intros i Hi. destruct (Nat.eqb i k) eqn:E.
      * apply Nat.eqb_eq in E. subst i.
        replace (Nat.eqb (S k) k) with false by (symmetry; apply Nat.eqb_neq; lia).
        rewrite E0. auto.
      * apply Nat.eqb_neq in E.
        replace (Nat.eqb (S i) k) with false by (symmetry; apply Nat.eqb_neq; lia).
        apply Hc. lia.
Qed.

Lemma run_ok_of_cycles:
  forall n t, cycles_ok O n (ctx_init ctx) t -> run_ok m ctx n (start_events m ++ t).
Proof.
  intros n t C. destruct (cycles_ok_fun _ _ _ _ C) as (sf & evf & E0 & Et & Hc).
  exists sf, evf. repeat split; auto.
  - rewrite Et. auto.
  - intros i Hi; apply Hc; lia.
Qed.

End CYCLES.

(** ** The generated node *)

(** The subscription that [main] registers for a subscribed topic. *)
Definition sub_of (tp : topic) : subscription :=
  mksub (tp_name tp) (tp_msg tp) (tp_queue tp) (callback_name (tp_cname tp)).

Lemma NoDup_map_inj_in:
  forall (A B : Type) (f : A -> B) l a b,
  NoDup (map f l) -> In a l -> In b l -> f a = f b -> a = b.
Proof.
  induction l as [|x l IH]; simpl; intros a b N Ha Hb E; [contradiction|].
  inversion N as [|? ? Hn N']; subst.
  destruct Ha as [<-|Ha]; destruct Hb as [<-|Hb]; auto.
  - elim Hn. rewrite E. apply in_map; auto.
  - elim Hn. rewrite <- E. apply in_map; auto.
Qed.

Lemma NoDup_app_left: forall (A : Type) (l1 l2 : list A), NoDup (l1 ++ l2) -> NoDup l1.
Proof.
  induction l1 as [|a l1 IH]; simpl; intros l2 N; [constructor|].
  inversion N as [|? ? Hn N']; subst. constructor; eauto.
  intros H; apply Hn, in_or_app; auto.
Qed.

Lemma NoDup_app_right: forall (A : Type) (l1 l2 : list A), NoDup (l1 ++ l2) -> NoDup l2.
Proof.
  induction l1 as [|a l1 IH]; simpl; intros l2 N; auto. inversion N; eauto.
Qed.

Lemma NoDup_flat_map_in:
  forall (A B : Type) (f : A -> list B) l a1 a2 x,
  NoDup (flat_map f l) -> In a1 l -> In a2 l -> In x (f a1) -> In x (f a2) -> a1 = a2.
Proof.
  induction l as [|b l IH]; simpl; intros a1 a2 x N H1 H2 X1 X2; [contradiction|].
  apply NoDup_app_inv in N. destruct N as (Nb & Nl & D).
  destruct H1 as [<-|H1], H2 as [<-|H2]; auto.
  - exfalso. apply (D x X1). apply in_flat_map; eauto.
  - exfalso. apply (D x X2). apply in_flat_map; eauto.
  - eapply IH; eauto.
Qed.

Lemma mem_wf_unchanged:
  forall mm mm' b, mem_wf mm -> unchanged_except mm mm' b -> get_block mm b <> None -> mem_wf mm'.
Proof.
  intros mm mm' b W [N O] L b' Hb'. rewrite N in Hb'.
  destruct (Pos.eq_dec b' b) as [->|Ne].
  - exfalso. apply L. apply W; auto.
  - rewrite O; auto.
Qed.

Lemma live_below:
  forall mm b v, mem_wf mm -> get_block mm b = Some v -> Pos.lt b (mem_next mm).
Proof.
  intros mm b v W G. destruct (Pos.lt_total b (mem_next mm)) as [H|[H|H]]; auto;
    rewrite W in G by lia; discriminate.
Qed.
