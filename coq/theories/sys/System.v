(** * Systems of nodes: composing the nodes' T2 over the topics that connect them *)

(** A system is a set of nodes, each generated and proved on its own
    (T2, [DDC.node_ddc]), wired by topics: a topic that node [A]
    publishes and node [B] subscribes to (after namespaces and
    remappings, DESIGN.md section "Systems").  This file composes the
    nodes' guarantees over such a connection.

    The *transport assumption* (what the network, that is ROS and the
    operating system, must do, and which no node can prove) is
    [delivered_from]: the newest message that [B]'s callback of the
    connecting topic received up to [B]'s [i]-th spin is the message
    [A] sent in one of its cycles [j] (as [A]'s trace records it: the
    message [DDC.sent] made of the [published_value] of that cycle).
    Every message is delivered, in order, within the environment's
    arrival schedule: the [j] of [B]'s [i]-th cycle is the latest cycle
    of [A] whose message [B] received.

    - Section "Links" ([link_value]): under the transport assumption, a
      subscriber's input fed by a field that the publisher's output
      relation writes holds, in the subscriber's cycle [i], exactly the
      value of the publisher's controller output in cycle [j]: the
      value the upstream controller computed.  Its hypotheses are the
      two nodes' cycle facts as T2 gives them ([input_values] of [B]'s
      cycle, [published_value] of [A]'s), facts about the two models
      that a system's file decides by computation ([link_ok]), and
      freshness (no fallback value replaced the field).
    - Section "Links between whole runs" ([link_cycles],
      [system_link]): the same over two decomposed runs, and over any
      runs of the two programs from the nodes' T2 ([link_holds]).
    - Section "Chains over the nodes' runs" ([chain_runs]): a chain
      input topic -> node -> topic -> ... -> output topic is its nodes,
      its links and the last node's output relations; from the nodes'
      T2 and the chain's facts, for ANY runs of its programs there is
      one T2 decomposition of each run along which every link holds and
      the last node publishes what its controller computed
      ([chain_holds]); a middle node's decomposition is shared by the
      link into it and the link out of it, so the facts compose.
    - Section "Chains" ([chain_value]) composes links over an interface
      of a chain (what each controller receives, computes and publishes
      at each cycle, the upstream cycle delivered): each controller
      receives what the controller upstream computed at the delivered
      cycle, back to the external input; [chain_run_value] builds that
      interface from the real runs of a [chain_holds].

    Definitions and proofs only; no axiom. *)

From Coq Require Import String List ZArith Bool Lia.
From ROSGen Require Import Errors Syntax Values Memory Environment Semantics NodeModel Wellformed Generator DDC.
Import ListNotations.

(** ** Facts about received messages *)

Lemma last_on_topic:
  forall name l a, last_on name l = Some a -> ar_topic a = name /\ In a l.
Proof.
  intros name l; induction l as [|b l IH]; simpl; intros a H; try discriminate.
  destruct (last_on name l) as [v|] eqn:L.
  - inversion H; subst. destruct (IH a eq_refl); auto.
  - destruct (string_dec (ar_topic b) name) as [E|E]; inversion H; subst; auto.
Qed.

Lemma received_on_incl:
  forall m tp msgs a, In a (received_on m tp msgs) -> In a msgs.
Proof.
  intros m tp msgs; induction msgs as [|b rest IH]; simpl; intros a H; auto.
  apply in_app_or in H. destruct H as [H|H]; auto.
  destruct (_ && _ && _); simpl in H; [destruct H as [H|H]; auto; contradiction|contradiction].
Qed.

(** The newest arrival is an arrival of the environment, on the topic. *)
Lemma newest_arrival_in:
  forall CS m (ctx : ros_context CS) tp i a,
  newest_arrival m ctx tp i = Some a ->
  ar_topic a = tp_name tp /\ exists k, In a (ctx_arrivals ctx k).
Proof.
  intros CS m ctx tp i a H. unfold newest_arrival in H.
  destruct (last_on_topic _ _ _ H) as [E I]. split; auto.
  apply in_flat_map in I. destruct I as (k & _ & I). exists k. eapply received_on_incl; eauto.
Qed.

(** The newest message depends on a topic's ROS name, message struct
    and queue size only. *)
Lemma received_on_ext:
  forall m t1 t2 l, tp_name t1 = tp_name t2 -> tp_queue t1 = tp_queue t2 -> tp_msg t1 = tp_msg t2 ->
  received_on m t1 l = received_on m t2 l.
Proof.
  intros m t1 t2 l N Q M. induction l as [|a l IH]; simpl; auto. rewrite N, Q, M, IH. reflexivity.
Qed.

Lemma newest_ext:
  forall CS m (ctx : ros_context CS) t1 t2 i,
  tp_name t1 = tp_name t2 -> tp_queue t1 = tp_queue t2 -> tp_msg t1 = tp_msg t2 ->
  newest m ctx t1 i = newest m ctx t2 i /\ newest_time m ctx t1 i = newest_time m ctx t2 i.
Proof.
  intros CS m ctx t1 t2 i N Q M.
  assert (E: newest_arrival m ctx t1 i = newest_arrival m ctx t2 i).
  { unfold newest_arrival. rewrite N. f_equal. apply flat_map_ext. intros j. apply received_on_ext; auto. }
  unfold newest, newest_time, converted. rewrite E, M. split; reflexivity.
Qed.

(** ** Links *)

(** The transport assumption for one connection, at [B]'s cycle [i]:
    the newest message [B]'s callback of topic [tpB] received up to its
    [i]-th spin is the message that [A] sent on its topic [tpA], [mv]
    being what [A]'s output glue built in the cycle it was published
    (ROS carries [DDC.sent mA tpA mv]). *)
Definition delivered_from {CS : Type} (mB : node_model) (ctxB : ros_context CS) (tpB : topic) (i : nat)
                          (mA : node_model) (tpA : topic) (mv : mval) : Prop :=
  exists a, newest_arrival mB ctxB tpB i = Some a /\ ar_msg a = sent mA tpA mv.

(** The facts about the two models that make a link: [tpA] is a
    published topic of [A] (every published topic of [A] with its ROS
    name has its C name and message struct), [tpB] a subscribed topic of
    [B], the only one with its C name; the two are one topic of the ROS
    graph: [gA] and [gB] give each node's topic names as the graph
    resolves them (namespace and remappings, DESIGN.md section 10), and
    they agree; output relation [o] of [A] writes field [or_path o] of
    [tpA], input relation [ir] of [B] reads the same field of [tpB]; in
    both nodes' message types the field is a scalar reached through no
    bounded sequence.  A system's file decides [link_ok] by
    computation. *)
Definition link_ok (gA : string -> string) (mA : node_model) (tpA : topic) (o : outrel)
                   (gB : string -> string) (mB : node_model) (tpB : topic) (ir : inrel) : bool :=
     existsb (fun t => topic_eqb (tp_name t) (tp_name tpA) && String.eqb (tp_cname t) (tp_cname tpA)
                       && String.eqb (tp_msg t) (tp_msg tpA) && is_published t) (nm_topics mA)
  && forallb (fun t => negb (is_published t && topic_eqb (tp_name t) (tp_name tpA))
                       || (String.eqb (tp_cname t) (tp_cname tpA) && String.eqb (tp_msg t) (tp_msg tpA)))
             (nm_topics mA)
  && existsb (fun t => topic_eqb (tp_name t) (tp_name tpB) && String.eqb (tp_cname t) (tp_cname tpB)
                       && String.eqb (tp_msg t) (tp_msg tpB) && Nat.eqb (tp_queue t) (tp_queue tpB)
                       && is_subscribed t) (nm_topics mB)
  && String.eqb (gA (tp_name tpA)) (gB (tp_name tpB))
  && Nat.eqb (length (filter (fun t => String.eqb (tp_cname t) (tp_cname tpB)) (subscribed mB))) 1
  && existsb (fun o' => String.eqb (or_output o') (or_output o) && path_eqb (or_elem o') (or_elem o)
                        && String.eqb (or_topic o') (or_topic o) && path_eqb (or_path o') (or_path o))
             (nm_outrels mA)
  && String.eqb (or_topic o) (tp_cname tpA)
  && existsb (fun ir' => String.eqb (ir_topic ir') (ir_topic ir) && path_eqb (ir_path ir') (ir_path ir)
                         && String.eqb (ir_input ir') (ir_input ir) && path_eqb (ir_elem ir') (ir_elem ir))
             (nm_inrels mB)
  && String.eqb (ir_topic ir) (tp_cname tpB)
  && path_eqb (or_path o) (ir_path ir)
  && unbounded_path (composites mA) (Tstruct (tp_msg tpA)) (path_steps (or_path o))
  && unbounded_path (composites mB) (Tstruct (tp_msg tpB)) (path_steps (ir_path ir))
  && match type_at (composites mA) (Tstruct (tp_msg tpA)) (path_steps (or_path o)),
           type_at (composites mB) (Tstruct (tp_msg tpB)) (path_steps (ir_path ir)) with
     | Some ta, Some tb => is_scalar_type ta && is_scalar_type tb
     | _, _ => false
     end.

Lemma existsb_in:
  forall {A} (f : A -> bool) l, existsb f l = true -> exists x, In x l /\ f x = true.
Proof. intros A f l H. apply existsb_exists in H. exact H. Qed.

Lemma filter_one:
  forall {A} (f : A -> bool) l x y,
  length (filter f l) = 1%nat -> In x l -> f x = true -> In y l -> f y = true -> x = y.
Proof.
  intros A f l x y L Ix Fx Iy Fy.
  assert (Hx: In x (filter f l)) by (apply filter_In; auto).
  assert (Hy: In y (filter f l)) by (apply filter_In; auto).
  destruct (filter f l) as [|a [|b r]]; simpl in L; try discriminate.
  destruct Hx as [Hx|[]]; destruct Hy as [Hy|[]]; congruence.
Qed.

(** Whether the input of relation [ir] keeps the newest message's field
    in [B]'s cycle [i]: it has no fallback value (rule 4.12), or its
    topic is not stale at the cycle's time. *)
Definition kept_fresh {CS : Type} (mB : node_model) (ctxB : ros_context CS) (tpB : topic) (ir : inrel) (i : nat)
  : Prop :=
  find_assoc (ir_input ir) (nm_fallbacks mB) = None
  \/ stale mB (ir_topic ir) (newest_time mB ctxB tpB i) (ctx_time ctxB (S i)) = false.

(** One link: in [B]'s cycle [i], the input of [ir] holds the value that
    [A]'s controller computed for the output of [o] in the cycle [j]
    whose message [B] received last ([y] the controller's outputs of
    [A]'s cycle [j], [mv] the message its output glue built then). *)
Theorem link_value:
  forall gA gB mA mB (CS : Type) (ctxB : ros_context CS) i u tpA tpB o ir y now g mv,
  link_ok gA mA tpA o gB mB tpB ir = true ->
  arrivals_wt mB ctxB ->
  input_values mB ctxB i u ->
  published_value mA y now g tpA mv ->
  delivered_from mB ctxB tpB i mA tpA mv ->
  kept_fresh mB ctxB tpB ir i ->
  exists v,
     mval_get y (Sfield (or_output o) :: path_steps (or_elem o)) = Some (MVscalar v)
  /\ mval_get u (input_leaf ir) = Some (MVscalar v).
Proof.
  intros gA gB mA mB CS ctxB i u tpA tpB o ir y now g mv L WT IV PV (a & NA & MA) KF.
  unfold link_ok in L. repeat rewrite andb_true_iff in L.
  destruct L as [[[[[[[[[[[[_ _] SB] NAB] One] Oin] Ot] Iin] It] Pe] UA] UB] Ty].
  destruct (existsb_in _ _ SB) as (tB & TBin & TB). repeat rewrite andb_true_iff in TB.
  destruct TB as ((((N1 & C1) & M1) & Q1) & S1).
  destruct (existsb_in _ _ Oin) as (o' & Oin' & Oe). repeat rewrite andb_true_iff in Oe.
  destruct Oe as (((Oe1 & Oe2) & Oe3) & Oe4).
  destruct (existsb_in _ _ Iin) as (ir' & Iin' & Ie). repeat rewrite andb_true_iff in Ie.
  destruct Ie as (((Ie1 & Ie2) & Ie3) & Ie4).
  apply String.eqb_eq in Ot. apply String.eqb_eq in It. apply path_eqb_iff in Pe.
  apply Nat.eqb_eq in One.
  assert (Eir: ir' = ir).
  { destruct ir, ir'; simpl in *. apply String.eqb_eq in Ie1. apply String.eqb_eq in Ie3.
    apply path_eqb_iff in Ie2. apply path_eqb_iff in Ie4. subst. reflexivity. }
  assert (Eo: o' = o).
  { destruct o, o'; simpl in *. apply String.eqb_eq in Oe1. apply String.eqb_eq in Oe3.
    apply path_eqb_iff in Oe2. apply path_eqb_iff in Oe4. subst. reflexivity. }
  subst ir' o'.
  (* The publisher's side: the output relation's field holds the output. *)
  destruct PV as (PT & PO & _).
  destruct (PO o Oin' Ot) as (v & Gy & Gmv).
  exists v. split; [exact Gy|].
  destruct (type_at (composites mA) (Tstruct (tp_msg tpA)) (path_steps (or_path o))) as [ta|] eqn:TA;
    [|discriminate].
  destruct (type_at (composites mB) (Tstruct (tp_msg tpB)) (path_steps (ir_path ir))) as [tb|] eqn:TB;
    [|discriminate].
  (* What ROS carries: the scalar field as the glue wrote it. *)
  assert (Gs: mval_get (sent mA tpA mv) (path_steps (or_path o)) = Some (MVscalar v))
    by (eapply sent_scalar; eauto).
  (* The subscriber's side: the relation's topic is [tpB]. *)
  destruct IV as (_ & IR & _).
  destruct (IR ir Iin') as (tp & v' & Tin & Tc & Gn & Gu).
  assert (Etp: tp = tB).
  { assert (Tin' : In tB (subscribed mB)) by (unfold subscribed; apply filter_In; auto).
    apply String.eqb_eq in C1.
    apply (filter_one (fun t => String.eqb (tp_cname t) (tp_cname tpB)) (subscribed mB) tp tB One Tin).
    - apply String.eqb_eq. congruence.
    - exact Tin'.
    - apply String.eqb_eq. exact C1. }
  subst tp.
  (* tB and tpB agree on everything the newest message depends on *)
  assert (Etb: newest mB ctxB tB i = newest mB ctxB tpB i /\ newest_time mB ctxB tB i = newest_time mB ctxB tpB i).
  { apply newest_ext.
    - unfold topic_eqb in N1. destruct (string_dec (tp_name tB) (tp_name tpB)); [auto|discriminate].
    - apply Nat.eqb_eq; exact Q1.
    - apply String.eqb_eq; exact M1. }
  destruct Etb as [En Et]. rewrite En in Gn. rewrite Et in Gu.
  destruct (newest_arrival_in _ _ _ _ _ _ NA) as (Ea & k & Ik).
  unfold newest in Gn. rewrite NA in Gn. unfold converted in Gn.
  assert (Ta: mval_has_type (composites mB) (Tstruct (tp_msg tpB)) (ar_msg a)).
  { assert (Tin' : In tB (subscribed mB)) by (unfold subscribed; apply filter_In; auto).
    specialize (WT k a tB Ik Tin'). clear -WT N1 M1 Ea.
    destruct tB as [n1 c1 ty1 d1 s1 q1], tpB as [n2 c2 ty2 d2 s2 q2]; simpl in *.
    unfold topic_eqb in N1. destruct (string_dec n1 n2); [|discriminate].
    apply String.eqb_eq in M1. subst. apply WT. auto. }
  rewrite <- MA, Pe in Gs.
  rewrite (clamp_get _ _ _ _ tb _ Ta UB TB Gs) in Gn. simpl in Gn. inversion Gn; subst v'.
  unfold input_leaf. rewrite Gu. unfold fed_value.
  destruct KF as [KF|KF].
  - destruct (stale _ _ _ _); [rewrite KF|]; reflexivity.
  - rewrite KF. reflexivity.
Qed.


(** ** Links between whole runs (from the nodes' T2) *)

Lemma Forall2_In_combine:
  forall {A B} (P : A -> B -> Prop) l1 l2 x y,
  Forall2 P l1 l2 -> In (x, y) (combine l1 l2) -> P x y.
Proof.
  intros A B P l1 l2 x y F. induction F as [|a b l1 l2 Pab F IH]; simpl; intros H; [contradiction|].
  destruct H as [H|H]; [inversion H; subst; auto|auto].
Qed.

(** [published_value] and [sent] depend on a topic's C name and message
    struct only. *)
Lemma published_value_ext:
  forall m y now g t1 t2 mv,
  tp_cname t1 = tp_cname t2 -> tp_msg t1 = tp_msg t2 ->
  published_value m y now g t1 mv -> published_value m y now g t2 mv.
Proof.
  intros m y now g t1 t2 mv C M H. unfold published_value in *. rewrite <- C, <- M. exact H.
Qed.

Lemma sent_ext:
  forall m t1 t2 mv, tp_msg t1 = tp_msg t2 -> sent m t1 mv = sent m t2 mv.
Proof. intros m t1 t2 mv M. unfold sent. rewrite M. reflexivity. Qed.

(** A publication in a correct cycle: the message of one of the model's
    published topics, built from the cycle's controller outputs. *)
Lemma cycle_publication:
  forall m CS (ctx : ros_context CS) i s evs s' name msg,
  cycle_ok m ctx i s evs s' -> In (Epublish name msg) evs ->
  exists u y rest tp mv,
     evs = Estep u y :: rest
  /\ ctx_step ctx s u = (s', y)
  /\ In tp (published m) /\ name = tp_name tp /\ msg = sent m tp mv
  /\ published_value m y (ctx_time ctx (S i)) (newest_by m ctx i) tp mv.
Proof.
  intros m CS ctx i s evs s' name msg (u & y & mvs & E & _ & St & F) I.
  subst evs. destruct I as [I|I]; [discriminate|].
  apply in_app_or in I. destruct I as [I|[I|[]]]; [|discriminate].
  unfold publish_events in I. apply in_map_iff in I. destruct I as ([tp mv] & Ev & Ic).
  simpl in Ev. inversion Ev; subst.
  exists u, y, (publish_events m (published m) mvs ++ [Esleep (nm_period_ms m)]), tp, mv.
  split; [reflexivity|]. split; [exact St|].
  split; [apply in_combine_l in Ic; exact Ic|]. split; [reflexivity|]. split; [reflexivity|].
  exact (Forall2_In_combine _ _ _ _ _ F Ic).
Qed.

(** The link between two decomposed runs: given T2's decomposition of
    a run of [A] (states [sA], cycles [evsA]) and of one of [B], for
    every cycle [i] of [B] and [j] of [A], if the newest message [B]'s
    callback of [tpB] received up to its [i]-th spin is one that [A]
    published on [tpA] in its cycle [j] (the transport assumption) and
    no fallback value replaced the input ([kept_fresh]), then [A]'s
    controller computed, in cycle [j], an output whose field [o] is a
    value [v], and [B]'s controller receives [v] on the input of [ir] in
    cycle [i]. *)
Lemma link_cycles:
  forall gA gB mA mB tpA o tpB ir (CSA : Type) (ctxA : ros_context CSA) nA (sA : nat -> CSA) evsA
         (CSB : Type) (ctxB : ros_context CSB) nB (sB : nat -> CSB) evsB,
  link_ok gA mA tpA o gB mB tpB ir = true -> arrivals_wt mB ctxB ->
  (forall j, (j < nA)%nat -> cycle_ok mA ctxA j (sA j) (evsA j) (sA (S j))) ->
  (forall i, (i < nB)%nat -> cycle_ok mB ctxB i (sB i) (evsB i) (sB (S i))) ->
  forall i j, (i < nB)%nat -> (j < nA)%nat ->
  (exists a, newest_arrival mB ctxB tpB i = Some a /\ In (Epublish (tp_name tpA) (ar_msg a)) (evsA j)) ->
  kept_fresh mB ctxB tpB ir i ->
  exists uA yA restA uB yB restB v,
     evsA j = Estep uA yA :: restA
  /\ ctx_step ctxA (sA j) uA = (sA (S j), yA)
  /\ evsB i = Estep uB yB :: restB
  /\ mval_get yA (Sfield (or_output o) :: path_steps (or_elem o)) = Some (MVscalar v)
  /\ mval_get uB (input_leaf ir) = Some (MVscalar v).
Proof.
  intros gA gB mA mB tpA o tpB ir CSA ctxA nA sA evsA CSB ctxB nB sB evsB L WB CyA CyB i j Hi Hj (a & NA & IP) KF.
  destruct (cycle_publication _ _ _ _ _ _ _ _ _ (CyA j Hj) IP)
    as (uA & yA & restA & tp & mv & EA & StA & Tp & Nm & Msg & PV).
  (* the publishing topic is [tpA] as far as the message goes *)
  assert (L' := L). unfold link_ok in L'. repeat rewrite andb_true_iff in L'.
  destruct L' as [[[[[[[[[[[[_ PU] _] _] _] _] _] _] _] _] _] _] _].
  assert (Tin : In tp (nm_topics mA) /\ is_published tp = true)
    by (unfold published in Tp; apply filter_In in Tp; exact Tp).
  destruct Tin as [Tin Pub].
  rewrite forallb_forall in PU. specialize (PU tp Tin). rewrite Pub in PU.
  assert (Nt : topic_eqb (tp_name tp) (tp_name tpA) = true)
    by (unfold topic_eqb; destruct (string_dec (tp_name tp) (tp_name tpA)); congruence).
  rewrite Nt in PU. simpl in PU. rewrite andb_true_iff in PU. destruct PU as [Ce Me].
  apply String.eqb_eq in Ce. apply String.eqb_eq in Me.
  assert (PV' : published_value mA yA (ctx_time ctxA (S j)) (newest_by mA ctxA j) tpA mv)
    by (eapply published_value_ext; eauto).
  assert (DF : delivered_from mB ctxB tpB i mA tpA mv).
  { exists a. split; auto. rewrite Msg. apply sent_ext. exact Me. }
  destruct (CyB i Hi) as (uB & yB & mvsB & EB & IVB & StB & _).
  destruct (link_value gA gB mA mB CSB ctxB i uB tpA tpB o ir yA _ _ mv L WB IVB PV' DF KF) as (v & Gy & Gu).
  exists uA, yA, restA, uB, yB, (publish_events mB (published mB) mvsB ++ [Esleep (nm_period_ms mB)]), v.
  split; [exact EA|]. split; [exact StA|]. split; [exact EB|]. split; [exact Gy|exact Gu].
Qed.

(** What a link guarantees of the runs of its two nodes ([A] publishing,
    [B] subscribing), in every environment of each with well-typed
    messages and controller outputs, for any numbers of cycles: their
    traces are the nodes' starts followed by cycles (T2's
    decomposition), and for every cycle [i] of [B] and [j] of [A], if
    the newest message [B]'s callback of [tpB] received up to its
    [i]-th spin is the message [A] published on [tpA] in its cycle [j]
    (the transport assumption: ROS delivered it, and nothing newer), and
    no fallback value replaced the input ([kept_fresh]), then [A]'s
    controller computed, in cycle [j] (stepped from its state [sA j] to
    [sA (S j)]), an output whose field [o] is a value [v], and [B]'s
    controller receives [v] on the input of [ir] in cycle [i]. *)
Definition link_holds (mA : node_model) (pA : program) (tpA : topic) (o : outrel)
                      (mB : node_model) (pB : program) (tpB : topic) (ir : inrel) : Prop :=
  forall (CSA : Type) (ctxA : ros_context CSA) nA tA (CSB : Type) (ctxB : ros_context CSB) nB tB,
  arrivals_wt mA ctxA -> controller_wt mA ctxA -> arrivals_wt mB ctxB -> controller_wt mB ctxB ->
  program_behaves pA ctxA nA tA -> program_behaves pB ctxB nB tB ->
  exists (sA : nat -> CSA) (evsA : nat -> trace) (sB : nat -> CSB) (evsB : nat -> trace),
     sA O = ctx_init ctxA /\ tA = start_events mA ++ concat (map evsA (seq 0 nA))
  /\ sB O = ctx_init ctxB /\ tB = start_events mB ++ concat (map evsB (seq 0 nB))
  /\ forall i j, (i < nB)%nat -> (j < nA)%nat ->
     (exists a, newest_arrival mB ctxB tpB i = Some a /\ In (Epublish (tp_name tpA) (ar_msg a)) (evsA j)) ->
     kept_fresh mB ctxB tpB ir i ->
     exists uA yA restA uB yB restB v,
        evsA j = Estep uA yA :: restA
     /\ ctx_step ctxA (sA j) uA = (sA (S j), yA)
     /\ evsB i = Estep uB yB :: restB
     /\ mval_get yA (Sfield (or_output o) :: path_steps (or_elem o)) = Some (MVscalar v)
     /\ mval_get uB (input_leaf ir) = Some (MVscalar v).

(** The link theorem: the two nodes' T2 ([node_ddc], proved for each
    generated node as [<node>_ddc]) and the link's facts give
    [link_holds]. *)
Theorem system_link:
  forall gA gB mA pA mB pB tpA o tpB ir,
  node_ddc mA pA -> node_ddc mB pB ->
  link_ok gA mA tpA o gB mB tpB ir = true ->
  link_holds mA pA tpA o mB pB tpB ir.
Proof.
  intros gA gB mA pA mB pB tpA o tpB ir DA DB L.
  intros CSA ctxA nA tA CSB ctxB nB tB WA CA WB CB BA BB.
  destruct (DA CSA ctxA nA WA CA) as [_ RA]. destruct (RA tA BA) as (sA & evsA & SA0 & TA & CyA).
  destruct (DB CSB ctxB nB WB CB) as [_ RB]. destruct (RB tB BB) as (sB & evsB & SB0 & TB & CyB).
  exists sA, evsA, sB, evsB. repeat split; auto.
  exact (link_cycles gA gB mA mB tpA o tpB ir CSA ctxA nA sA evsA CSB ctxB nB sB evsB L WB CyA CyB).
Qed.

(** ** Publishing what the controller computed *)

(** The publisher's half of [link_ok], for a chain's external output:
    [tp] is a published topic of [m] (every published topic with its ROS
    name has its C name and message struct), output relation [o] writes
    field [or_path o] of [tp], a scalar reached through no bounded
    sequence. *)
Definition out_ok (m : node_model) (tp : topic) (o : outrel) : bool :=
     existsb (fun t => topic_eqb (tp_name t) (tp_name tp) && String.eqb (tp_cname t) (tp_cname tp)
                       && String.eqb (tp_msg t) (tp_msg tp) && is_published t) (nm_topics m)
  && forallb (fun t => negb (is_published t && topic_eqb (tp_name t) (tp_name tp))
                       || (String.eqb (tp_cname t) (tp_cname tp) && String.eqb (tp_msg t) (tp_msg tp)))
             (nm_topics m)
  && existsb (fun o' => String.eqb (or_output o') (or_output o) && path_eqb (or_elem o') (or_elem o)
                        && String.eqb (or_topic o') (or_topic o) && path_eqb (or_path o') (or_path o))
             (nm_outrels m)
  && String.eqb (or_topic o) (tp_cname tp)
  && unbounded_path (composites m) (Tstruct (tp_msg tp)) (path_steps (or_path o))
  && match type_at (composites m) (Tstruct (tp_msg tp)) (path_steps (or_path o)) with
     | Some t => is_scalar_type t
     | None => false
     end.

Lemma Forall2_combine_in:
  forall {A B} (P : A -> B -> Prop) l1 l2 x,
  Forall2 P l1 l2 -> In x l1 -> exists y, In (x, y) (combine l1 l2) /\ P x y.
Proof.
  intros A B P l1 l2 x F. induction F as [|a b l1 l2 Pab F IH]; simpl; intros H; [contradiction|].
  destruct H as [H|H]; [subst; exists b; auto|].
  destruct (IH H) as (y & I & Py). exists y; auto.
Qed.

Lemma outrel_eq:
  forall o o' : outrel,
  String.eqb (or_output o') (or_output o) && path_eqb (or_elem o') (or_elem o)
  && String.eqb (or_topic o') (or_topic o) && path_eqb (or_path o') (or_path o) = true -> o' = o.
Proof.
  intros [a b c d] [a' b' c' d'] H; simpl in *. repeat rewrite andb_true_iff in H.
  destruct H as (((H1 & H2) & H3) & H4).
  apply String.eqb_eq in H1. apply String.eqb_eq in H3. apply path_eqb_iff in H2. apply path_eqb_iff in H4.
  subst. reflexivity.
Qed.

(** In a correct cycle, a node with [out_ok] publishes on [tp] (at least
    one message) and every message it publishes there carries in the
    field of [o] the value [v] its controller computed on [o] in that
    cycle. *)
Lemma published_out:
  forall m CS (ctx : ros_context CS) i s evs s' tp o,
  cycle_ok m ctx i s evs s' -> out_ok m tp o = true ->
  exists u y rest v,
     evs = Estep u y :: rest /\ ctx_step ctx s u = (s', y)
  /\ mval_get y (Sfield (or_output o) :: path_steps (or_elem o)) = Some (MVscalar v)
  /\ (exists msg, In (Epublish (tp_name tp) msg) evs)
  /\ (forall msg, In (Epublish (tp_name tp) msg) evs -> mval_get msg (path_steps (or_path o)) = Some (MVscalar v)).
Proof.
  intros m CS ctx i s evs s' tp o Cy L.
  assert (L' := L). unfold out_ok in L'. repeat rewrite andb_true_iff in L'.
  destruct L' as [[[[[Ex PU] Oin] Ot] U] Ty].
  apply String.eqb_eq in Ot. destruct (existsb_in _ _ Oin) as (o' & Oin' & Oe). apply outrel_eq in Oe. subst o'.
  destruct (type_at (composites m) (Tstruct (tp_msg tp)) (path_steps (or_path o))) as [t|] eqn:TA; [|discriminate].
  (* every message published under [tp]'s name carries the output *)
  assert (All: forall msg, In (Epublish (tp_name tp) msg) evs ->
            exists u y rest v, evs = Estep u y :: rest /\ ctx_step ctx s u = (s', y)
            /\ mval_get y (Sfield (or_output o) :: path_steps (or_elem o)) = Some (MVscalar v)
            /\ mval_get msg (path_steps (or_path o)) = Some (MVscalar v)).
  { intros msg IP.
    destruct (cycle_publication _ _ _ _ _ _ _ _ _ Cy IP) as (u & y & rest & tp' & mv & E & St & Tp & Nm & Msg & PV).
    assert (Tin : In tp' (nm_topics m) /\ is_published tp' = true)
      by (unfold published in Tp; apply filter_In in Tp; exact Tp).
    destruct Tin as [Tin Pub].
    assert (PU' := PU). rewrite forallb_forall in PU'. specialize (PU' tp' Tin). rewrite Pub in PU'.
    assert (Nt : topic_eqb (tp_name tp') (tp_name tp) = true)
      by (unfold topic_eqb; destruct (string_dec (tp_name tp') (tp_name tp)); congruence).
    rewrite Nt in PU'. simpl in PU'. rewrite andb_true_iff in PU'. destruct PU' as [Ce Me].
    apply String.eqb_eq in Ce. apply String.eqb_eq in Me.
    assert (PV' : published_value m y (ctx_time ctx (S i)) (newest_by m ctx i) tp mv)
      by (eapply published_value_ext; eauto).
    destruct PV' as (PT & PO & _).
    destruct (PO o Oin' Ot) as (v & Gy & Gmv).
    exists u, y, rest, v. split; [exact E|]. split; [exact St|]. split; [exact Gy|].
    rewrite Msg, (sent_ext _ _ _ _ Me). eapply sent_scalar; eauto. }
  (* and there is one: the published topic of [tp]'s name *)
  destruct (existsb_in _ _ Ex) as (t0 & T0in & T0). repeat rewrite andb_true_iff in T0.
  destruct T0 as (((N0 & _) & _) & P0).
  assert (T0p : In t0 (published m)) by (unfold published; apply filter_In; auto).
  destruct Cy as (u & y & mvs & E & IV & St & F).
  destruct (Forall2_combine_in _ _ _ _ F T0p) as (mv & Ic & _).
  assert (IP : In (Epublish (tp_name tp) (sent m t0 mv)) evs).
  { rewrite E. right. apply in_or_app. left. unfold publish_events. apply in_map_iff.
    exists (t0, mv). split; [|exact Ic]. simpl. f_equal.
    unfold topic_eqb in N0. destruct (string_dec (tp_name t0) (tp_name tp)); [auto|discriminate]. }
  assert (Cy : cycle_ok m ctx i s evs s') by (exists u, y, mvs; auto).
  destruct (All _ IP) as (u' & y' & rest & v & E' & St' & Gy & _).
  exists u', y', rest, v. split; [exact E'|]. split; [exact St'|]. split; [exact Gy|]. split; [eauto|].
  intros msg IPm. destruct (All msg IPm) as (u2 & y2 & rest2 & v2 & E2 & _ & Gy2 & Gm).
  rewrite E' in E2. inversion E2; subst. rewrite Gy in Gy2. inversion Gy2; subst. exact Gm.
Qed.

(** ** Chains over the nodes' runs *)

(** A chain input topic -> node -> topic -> ... -> output topic: its
    nodes [ns] in chain order (each with its model, its program and the
    graph names of its topics), the links [ls] between consecutive nodes
    (a link [L] goes from node [cl_from L] to node [S (cl_from L)], on
    a publisher's output relation and a subscriber's input relation;
    several links may join the same two nodes, one per field), and the
    output relations [outs] of the last node on the chain's external
    output topic. *)
Record cnode : Type := mkcnode { cn_model : node_model; cn_prog : program; cn_graph : string -> string }.
Record clink : Type := mkclink { cl_from : nat; cl_tpA : topic; cl_out : outrel; cl_tpB : topic; cl_in : inrel }.
Record cout : Type := mkcout { co_topic : topic; co_out : outrel }.

(** One run of a node: the environment (controller states [r_CS], the
    context [r_ctx]), the number of cycles and the trace. *)
Record run : Type := mkrun { r_CS : Type; r_ctx : ros_context r_CS; r_n : nat; r_trace : trace }.

(** What a system's file proves about a chain by computation and from
    the nodes' T2: every node has [node_ddc], every link joins two
    consecutive nodes of the chain and has [link_ok], every output
    relation of the last node has [out_ok]. *)
Definition link_at (ns : list cnode) (L : clink) : Prop :=
  exists cA cB, nth_error ns (cl_from L) = Some cA /\ nth_error ns (S (cl_from L)) = Some cB
  /\ link_ok (cn_graph cA) (cn_model cA) (cl_tpA L) (cl_out L) (cn_graph cB) (cn_model cB) (cl_tpB L) (cl_in L) = true.

Definition out_at (ns : list cnode) (co : cout) : Prop :=
  exists c, nth_error ns (pred (length ns)) = Some c /\ out_ok (cn_model c) (co_topic co) (co_out co) = true.

Definition chain_ok (ns : list cnode) (ls : list clink) (outs : list cout) : Prop :=
  Forall (fun c => node_ddc (cn_model c) (cn_prog c)) ns /\ Forall (link_at ns) ls /\ Forall (out_at ns) outs.

(** The runs considered: node [l]'s run [rs l] is a behaviour of its
    program in an environment with well-typed messages and controller
    outputs, any environment and any number of cycles. *)
Definition runs_of (ns : list cnode) (rs : nat -> run) : Prop :=
  forall l c, nth_error ns l = Some c ->
     arrivals_wt (cn_model c) (r_ctx (rs l)) /\ controller_wt (cn_model c) (r_ctx (rs l))
  /\ program_behaves (cn_prog c) (r_ctx (rs l)) (r_n (rs l)) (r_trace (rs l)).

(** T2's decomposition of a node's run: its start, then its cycles, the
    controller's states [s] chained from the initial state. *)
Definition decomposed (c : cnode) (r : run) (s : nat -> r_CS r) (evs : nat -> trace) : Prop :=
     s O = ctx_init (r_ctx r)
  /\ r_trace r = start_events (cn_model c) ++ concat (map evs (seq 0 (r_n r)))
  /\ forall i, (i < r_n r)%nat -> cycle_ok (cn_model c) (r_ctx r) i (s i) (evs i) (s (S i)).

(** What a cycle's events say: the value the controller received on the
    input of [ir], the value it computed on the output of [o] (the
    cycle starts with [Estep u y]: the controller read [u], wrote [y]). *)
Definition received (e : trace) (ir : inrel) : option val :=
  match e with
  | Estep u _ :: _ => match mval_get u (input_leaf ir) with Some (MVscalar v) => Some v | _ => None end
  | _ => None
  end.

Definition computed (e : trace) (o : outrel) : option val :=
  match e with
  | Estep _ y :: _ =>
      match mval_get y (Sfield (or_output o) :: path_steps (or_elem o)) with Some (MVscalar v) => Some v | _ => None end
  | _ => None
  end.

(** The transport assumption for link [L] ([delivered_from], with [A]'s
    message read from its trace): the newest message that node
    [S (cl_from L)] received on [cl_tpB L] up to its [i]-th spin is one
    that node [cl_from L] published on [cl_tpA L] in its cycle [j]. *)
Definition transported (ns : list cnode) (rs : nat -> run) (evs : nat -> nat -> trace) (L : clink) (i j : nat)
  : Prop :=
  exists cB a, nth_error ns (S (cl_from L)) = Some cB
  /\ newest_arrival (cn_model cB) (r_ctx (rs (S (cl_from L)))) (cl_tpB L) i = Some a
  /\ In (Epublish (tp_name (cl_tpA L)) (ar_msg a)) (evs (cl_from L) j).

Definition fresh_at (ns : list cnode) (rs : nat -> run) (L : clink) (i : nat) : Prop :=
  forall cB, nth_error ns (S (cl_from L)) = Some cB -> kept_fresh (cn_model cB) (r_ctx (rs (S (cl_from L)))) (cl_tpB L) (cl_in L) i.

(** The chain's links over the runs: whenever the transport delivered
    to node [S l]'s cycle [i] the message of node [l]'s cycle [j], and
    no fallback replaced the input, node [S l]'s controller received in
    cycle [i] the value node [l]'s controller computed in cycle [j]. *)
Definition chain_links (ns : list cnode) (ls : list clink) (rs : nat -> run) (evs : nat -> nat -> trace) : Prop :=
  forall L i j, In L ls ->
  (i < r_n (rs (S (cl_from L))))%nat -> (j < r_n (rs (cl_from L)))%nat ->
  transported ns rs evs L i j -> fresh_at ns rs L i ->
  exists v, computed (evs (cl_from L) j) (cl_out L) = Some v /\ received (evs (S (cl_from L)) i) (cl_in L) = Some v.

(** The chain's end: in every cycle the last node publishes on the
    external output, and every message it publishes there carries in
    the field of each output relation what its controller computed. *)
Definition chain_outputs (ns : list cnode) (outs : list cout) (rs : nat -> run) (evs : nat -> nat -> trace) : Prop :=
  forall co k, In co outs -> (k < r_n (rs (pred (length ns))))%nat ->
  exists v, computed (evs (pred (length ns)) k) (co_out co) = Some v
  /\ (exists msg, In (Epublish (tp_name (co_topic co)) msg) (evs (pred (length ns)) k))
  /\ (forall msg, In (Epublish (tp_name (co_topic co)) msg) (evs (pred (length ns)) k) ->
        mval_get msg (path_steps (or_path (co_out co))) = Some (MVscalar v)).

(** What the chain theorem says of every set of runs of the chain's
    programs: ONE decomposition of each node's run by T2 (states [s l],
    cycles [evs l]: each cycle steps the controller from [s l i] to
    [s l (S i)] on the inputs it received, [cycle_ok]), along which the
    links and the end of the chain hold.  Because the decomposition of a
    middle node is shared by the link into it and the link out of it,
    the facts compose: the value node [l + 1] receives in cycle [i] is
    the output node [l]'s controller computed in the delivered cycle [j]
    from its state [s l j] and the inputs it received in cycle [j],
    themselves computed upstream in the cycle delivered to node [l] at
    its cycle [j], ... back to the external input ([chain_run_value]). *)
Definition chain_holds (ns : list cnode) (ls : list clink) (outs : list cout) : Prop :=
  forall rs, runs_of ns rs ->
  exists (s : forall l, nat -> r_CS (rs l)) (evs : nat -> nat -> trace),
     (forall l c, nth_error ns l = Some c -> decomposed c (rs l) (s l) (evs l))
  /\ chain_links ns ls rs evs
  /\ chain_outputs ns outs rs evs.

(** One decomposition per node, for all the nodes at once (by recursion
    on the chain, no choice needed). *)
Lemma decompose_all:
  forall ns (rs : nat -> run),
  Forall (fun c => node_ddc (cn_model c) (cn_prog c)) ns -> runs_of ns rs ->
  exists (s : forall l, nat -> r_CS (rs l)) (evs : nat -> nat -> trace),
  forall l c, nth_error ns l = Some c -> decomposed c (rs l) (s l) (evs l).
Proof.
  induction ns as [|c0 ns IH]; intros rs D R.
  - exists (fun l _ => ctx_init (r_ctx (rs l))), (fun _ _ => []). intros l c H. destruct l; discriminate.
  - inversion D as [|x y D0 Ds]; subst.
    destruct (R O c0 eq_refl) as (W & C & B).
    destruct (D0 _ (r_ctx (rs O)) (r_n (rs O)) W C) as [_ RO].
    destruct (RO _ B) as (s0 & e0 & S0 & T0 & Cy0).
    assert (R' : runs_of ns (fun l => rs (S l))) by (intros l c H; exact (R (S l) c H)).
    destruct (IH (fun l => rs (S l)) Ds R') as (s' & e' & H').
    exists (fun l => match l return nat -> r_CS (rs l) with O => s0 | S l' => s' l' end),
           (fun l => match l with O => e0 | S l' => e' l' end).
    intros [|l] c H; simpl in H.
    + inversion H; subst. split; [exact S0|]. split; [exact T0|exact Cy0].
    + exact (H' l c H).
Qed.

(** The chain theorem: from the nodes' T2 and the chain's facts, for any
    runs of its programs. *)
Theorem chain_runs:
  forall ns ls outs, chain_ok ns ls outs -> chain_holds ns ls outs.
Proof.
  intros ns ls outs (D & LS & OS) rs R.
  destruct (decompose_all ns rs D R) as (s & evs & Dec).
  exists s, evs. split; [exact Dec|]. split.
  - intros L i j IL Hi Hj (cB & a & NB & NA & IP) KF.
    rewrite Forall_forall in LS. destruct (LS L IL) as (cA & cB' & NA' & NB' & Lok).
    rewrite NB in NB'. inversion NB'; subst cB'.
    destruct (Dec _ _ NA') as (_ & _ & CyA). destruct (Dec _ _ NB) as (_ & _ & CyB).
    destruct (R _ _ NB) as (WB & _ & _).
    destruct (link_cycles _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ Lok WB CyA CyB i j Hi Hj (ex_intro _ a (conj NA IP))
                (KF cB NB))
      as (uA & yA & restA & uB & yB & restB & v & EA & _ & EB & Gy & Gu).
    exists v. unfold computed, received. rewrite EA, EB, Gy, Gu. split; reflexivity.
  - intros co k Ico Hk.
    rewrite Forall_forall in OS. destruct (OS co Ico) as (c & Nc & Ok).
    destruct (Dec _ _ Nc) as (_ & _ & Cy).
    destruct (published_out _ _ _ _ _ _ _ _ _ (Cy k Hk) Ok) as (u & y & rest & v & E & _ & Gy & Ex & All).
    exists v. split; [unfold computed; rewrite E, Gy; reflexivity|]. split; [exact Ex|exact All].
Qed.

(** ** The composition along a chain *)

(** A chain, over an interface of its nodes: per node [l] of the chain
    (from 0), at its cycle [k] (below [ch_cycles l]), [ch_input l k] is
    the value its controller receives on the chain's relation into it,
    [ch_output l k] what it computes on the chain's relation out of it,
    [ch_published l k] the field its message carries; [ch_latest l k] is
    the cycle of node [l - 1] whose message node [l] received last at
    its cycle [k] ([None]: none yet; the input then holds what T2 says
    of a topic with no message, the zero message), as the transport
    delivered it.  [chain_run_value] builds this interface from the
    nodes' real runs. *)
Section Chains.

Variable V : Type.

Record chain_iface : Type := mkchain {
  ch_input : nat -> nat -> V;           (**r node, cycle: the value received *)
  ch_output : nat -> nat -> V;          (**r node, cycle: the value computed *)
  ch_published : nat -> nat -> V;       (**r node, cycle: the value published *)
  ch_latest : nat -> nat -> option nat; (**r node, cycle: the upstream cycle delivered *)
  ch_cycles : nat -> nat                (**r node: its number of cycles *)
}.

(** Each link of a chain of [n] nodes: when node [S l] received at its
    cycle [k] the message of node [l]'s cycle [j], its input is node
    [l]'s output in that cycle. *)
Definition node_links (c : chain_iface) (n : nat) : Prop :=
  forall l k j, (S l < n)%nat -> (k < ch_cycles c (S l))%nat -> ch_latest c (S l) k = Some j ->
  (j < ch_cycles c l)%nat /\ ch_input c (S l) k = ch_output c l j.

(** The last node publishes what its controller computed. *)
Definition last_published (c : chain_iface) (n : nat) : Prop :=
  forall k, (k < ch_cycles c (pred n))%nat -> ch_published c (pred n) k = ch_output c (pred n) k.

(** The cycles of the nodes upstream of node [l] at its cycle [k]
    through which a value reaches it: [trace_back c l k] is the list of
    cycles of nodes [l - 1], [l - 2], ..., 0 (stopping at the first
    node that had received nothing yet). *)
Fixpoint trace_back (c : chain_iface) (l k : nat) : list nat :=
  match l with
  | O => []
  | S l' => match ch_latest c (S l') k with
            | Some j => j :: trace_back c l' j
            | None => []
            end
  end.

(** Node [l]'s input at cycle [k] came down the chain: it is the output
    of node [l - 1] at the delivered cycle [j], node [l - 1]'s input at
    [j] came likewise from node [l - 2], ... back to the first node (or
    to a node that had received nothing yet). *)
Fixpoint traced (c : chain_iface) (l k : nat) : Prop :=
  match l with
  | O => True
  | S l' => match ch_latest c (S l') k with
            | Some j => (j < ch_cycles c l')%nat /\ ch_input c (S l') k = ch_output c l' j /\ traced c l' j
            | None => True
            end
  end.

(** The composition: along a chain whose links hold, every node's input
    at every cycle is the output of the node upstream at the cycle the
    transport delivered, whose input came likewise from upstream, back
    to the chain's external input; and the last node publishes what its
    controller computed on those inputs. *)
Theorem chain_value:
  forall c n, node_links c n -> last_published c n ->
     (forall l k, (l < n)%nat -> (k < ch_cycles c l)%nat -> traced c l k)
  /\ (forall k, (k < ch_cycles c (pred n))%nat -> ch_published c (pred n) k = ch_output c (pred n) k).
Proof.
  intros c n NL LP. split; auto.
  induction l as [|l IH]; intros k Hl Hk; simpl; auto.
  destruct (ch_latest c (S l) k) as [j|] eqn:E; auto.
  destruct (NL l k j Hl Hk E) as [Hj Eq]. split; [exact Hj|]. split; [exact Eq|].
  apply IH; [lia|exact Hj].
Qed.

(** The cycles [trace_back] lists are exactly the delivered ones: the
    first is the cycle of node [l - 1] that node [l] received last. *)
Lemma trace_back_head:
  forall c l k j, ch_latest c (S l) k = Some j -> trace_back c (S l) k = j :: trace_back c l j.
Proof. intros c l k j H. simpl. rewrite H. reflexivity. Qed.

End Chains.

Arguments mkchain {V}.
Arguments ch_input {V}.
Arguments ch_output {V}.
Arguments ch_published {V}.
Arguments ch_latest {V}.
Arguments ch_cycles {V}.

(** ** The composition over the nodes' real runs *)

(** The first message the trace of a cycle publishes on a topic. *)
Fixpoint published_on (e : trace) (name : string) : option mval :=
  match e with
  | [] => None
  | Epublish n msg :: r => if string_dec n name then Some msg else published_on r name
  | _ :: r => published_on r name
  end.

Lemma published_on_some:
  forall e name, (exists msg, In (Epublish name msg) e) ->
  exists msg, published_on e name = Some msg /\ In (Epublish name msg) e.
Proof.
  induction e as [|ev e IH]; simpl; intros name (msg & I); [contradiction|].
  destruct I as [I|I].
  - subst ev. destruct (string_dec name name) as [_|N]; [exists msg; auto|congruence].
  - destruct (IH name (ex_intro _ msg I)) as (m' & P & I').
    destruct ev as [| | | |n0 msg0|]; try (exists m'; auto; fail).
    destruct (string_dec n0 name) as [E|E]; [subst; exists msg0; auto|exists m'; auto].
Qed.

Definition published_field (e : trace) (name : string) (lp : NodeModel.path) : option val :=
  match published_on e name with
  | Some msg => match mval_get msg (path_steps lp) with Some (MVscalar v) => Some v | _ => None end
  | None => None
  end.

(** The interface of a chain built from its runs' decompositions [evs]:
    the chain's relations are one link per pair of consecutive nodes
    ([pick l], from node [l] to node [S l]) and one output relation
    [co] of the last node; [d] is what the transport delivered. *)
Definition run_iface (ns : list cnode) (rs : nat -> run) (evs : nat -> nat -> trace) (pick : nat -> clink)
                     (co : cout) (d : nat -> nat -> option nat) : chain_iface (option val) :=
  mkchain (fun l k => received (evs l k) (cl_in (pick (pred l))))
          (fun l k => if Nat.eqb l (pred (length ns)) then computed (evs l k) (co_out co)
                      else computed (evs l k) (cl_out (pick l)))
          (fun l k => published_field (evs l k) (tp_name (co_topic co)) (or_path (co_out co)))
          d
          (fun l => r_n (rs l)).

(** [chain_composed ns co pick]: the chain theorem over the real runs,
    composed along the links [pick 0], [pick 1], ... and ending on the
    output relation [co].  [chain_run_value] proves it (from any
    [chain_holds], e.g. a system's [<system>_chain_c]; [co] one of the
    chain's output relations): for any runs of the
    chain's programs (any environments with well-typed messages and
    controller outputs, any numbers of cycles), there is one T2
    decomposition of each node's run such that, when the transport
    delivered to each node [S l] at each of its cycles [k] the message
    of node [l]'s cycle [d (S l) k] on the picked link ([transported],
    with [kept_fresh]), the interface of the runs satisfies
    [chain_value]: every node's input at every cycle is what the
    controller upstream computed at the delivered cycle, back to the
    external input ([traced]), and the last node published what its
    controller computed. *)
Definition chain_composed (ns : list cnode) (co : cout) (pick : nat -> clink) : Prop :=
  forall rs, runs_of ns rs ->
  exists (s : forall l, nat -> r_CS (rs l)) (evs : nat -> nat -> trace),
     (forall l c, nth_error ns l = Some c -> decomposed c (rs l) (s l) (evs l))
  /\ forall d : nat -> nat -> option nat,
     (forall l k j, (S l < length ns)%nat -> (k < r_n (rs (S l)))%nat -> d (S l) k = Some j ->
        (j < r_n (rs l))%nat /\ transported ns rs evs (pick l) k j /\ fresh_at ns rs (pick l) k) ->
     let c := run_iface ns rs evs pick co d in
        (forall l k, (l < length ns)%nat -> (k < r_n (rs l))%nat -> traced _ c l k)
     /\ (forall k, (k < r_n (rs (pred (length ns))))%nat ->
           ch_published c (pred (length ns)) k = ch_output c (pred (length ns)) k
        /\ exists v, ch_output c (pred (length ns)) k = Some v).

Theorem chain_run_value:
  forall ns ls outs co (pick : nat -> clink), chain_holds ns ls outs -> In co outs ->
  (forall l, (S l < length ns)%nat -> In (pick l) ls /\ cl_from (pick l) = l) ->
  chain_composed ns co pick.
Proof.
  intros ns ls outs co pick CH Ico P rs R.
  destruct (CH rs R) as (s & evs & Dec & CL & CO).
  exists s, evs. split; [exact Dec|]. intros d T c.
  assert (NL : node_links _ c (length ns)).
  { intros l k j Hl Hk E. simpl in Hk, E. destruct (T l k j Hl Hk E) as (Hj & Tr & Fr).
    destruct (P l Hl) as [IL Fl].
    assert (Hk' : (k < r_n (rs (S (cl_from (pick l)))))%nat) by (rewrite Fl; exact Hk).
    assert (Hj' : (j < r_n (rs (cl_from (pick l))))%nat) by (rewrite Fl; exact Hj).
    destruct (CL (pick l) k j IL Hk' Hj' Tr Fr) as (v & Gc & Gr).
    rewrite Fl in Gc, Gr. split; [exact Hj|]. simpl.
    rewrite Gr. replace (Nat.eqb l (pred (length ns))) with false by (symmetry; apply Nat.eqb_neq; lia).
    rewrite Gc. reflexivity. }
  assert (LP : last_published _ c (length ns) /\ forall k, (k < r_n (rs (pred (length ns))))%nat ->
                 exists v, ch_output c (pred (length ns)) k = Some v).
  { enough (H : forall k, (k < r_n (rs (pred (length ns))))%nat ->
                  exists v, ch_output c (pred (length ns)) k = Some v
                         /\ ch_published c (pred (length ns)) k = Some v).
    { split; [intros k Hk|intros k Hk]; destruct (H k Hk) as (v & A & B); [congruence|eauto]. }
    intros k Hk. destruct (CO co k Ico Hk) as (v & Gc & Ex & All).
    exists v. simpl. rewrite Nat.eqb_refl. split; [exact Gc|].
    unfold published_field. destruct (published_on_some _ _ Ex) as (msg & Pm & Im).
    rewrite Pm, (All msg Im). reflexivity. }
  destruct LP as [LP Some_].
  destruct (chain_value _ c (length ns) NL LP) as [Tr Pu].
  split; [exact Tr|]. intros k Hk. split; [exact (Pu k Hk)|exact (Some_ k Hk)].
Qed.

(** A path of a chain: the link of each pair of consecutive nodes,
    given by its position in the chain's links [ls] ([idx]); a system's
    file decides [path_ok] by computation ([n]: the number of nodes). *)
Definition no_link : clink :=
  mkclink 0 (mktopic EmptyString EmptyString EmptyString Publish EmptyString 0) (mkoutrel EmptyString EmptyString [])
          (mktopic EmptyString EmptyString EmptyString Subscribe EmptyString 0) (mkinrel EmptyString [] EmptyString).

Definition path_pick (ls : list clink) (idx : list nat) (l : nat) : clink := nth (nth l idx 0) ls no_link.

Definition path_ok (n : nat) (ls : list clink) (idx : list nat) : bool :=
  Nat.eqb (length idx) (pred n)
  && forallb (fun li => Nat.ltb (snd li) (length ls) && Nat.eqb (cl_from (nth (snd li) ls no_link)) (fst li))
             (combine (seq 0 (length idx)) idx).

Lemma path_pick_ok:
  forall (ns : list cnode) n ls idx, length ns = n -> path_ok n ls idx = true ->
  forall l, (S l < length ns)%nat -> In (path_pick ls idx l) ls /\ cl_from (path_pick ls idx l) = l.
Proof.
  intros ns n ls idx Ln P l Hl. unfold path_ok in P. apply andb_true_iff in P. destruct P as [Li F].
  apply Nat.eqb_eq in Li. rewrite forallb_forall in F.
  assert (Hi : (l < length idx)%nat) by lia.
  assert (I : In (l, nth l idx 0) (combine (seq 0 (length idx)) idx)).
  { assert (C : nth l (combine (seq 0 (length idx)) idx) (0, 0)%nat = (nth l (seq 0 (length idx)) 0, nth l idx 0)%nat)
      by (apply combine_nth; apply seq_length).
    rewrite seq_nth in C by exact Hi. rewrite Nat.add_0_l in C.
    rewrite <- C. apply nth_In. rewrite combine_length, seq_length, Nat.min_id. exact Hi. }
  specialize (F _ I). simpl in F. apply andb_true_iff in F. destruct F as [Lt E].
  apply Nat.ltb_lt in Lt. apply Nat.eqb_eq in E. unfold path_pick.
  split; [apply nth_In; exact Lt|exact E].
Qed.
