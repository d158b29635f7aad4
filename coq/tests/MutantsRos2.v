(** * ROS 2 mutants: mutated deliveries of the rcl wrapper, refuted *)

(** The environment model's ROS 2 instance ([Environment.rcl_deliverable]:
    per subscription the newest [sub_queue] arrivals of its topic, which a
    KEEP_LAST history of that depth holds, taken oldest first, one
    subscription after the other; [ros_now] in the
    callback is the arrival's receipt time [ar_time]) is what the ROS 2
    wrapper does (DESIGN.md section 6.1).  Each mutant below is a wrapper
    that does something else, and each is refuted:

    - [oldest_deliverable]: the take keeps the OLDEST [q] arrivals instead
      of the newest (a KEEP_ALL reader taken from the front, or a history
      that drops new samples);
    - [minus_deliverable], [plus_deliverable]: a history depth off by one
      ([q - 1], [q + 1]);
    - [sorted_deliverable]: the callbacks run by a sort of all the taken
      messages on their receipt times, which reorders
      a subscription's own messages when their times decrease (Fast DDS's
      reception times are on the system clock, which may step back);
    - the receipt time from the wrong clock: [ros_now] in the callback is
      the time of the cycle (the ROS clock read when the previous spin
      returned, the wrapper's [g_now_ns] left as it was) instead of the
      message's receipt time.

    What each refutation shows:
    - the property T2's proof needs of a spin's deliveries
      ([Main.last_delivered_rcl_deliverable]: for distinct subscriptions
      and a depth of at least 1, the last message delivered to a
      subscription is the last arrival on its topic) fails for [oldest],
      [q - 1] and the sort, on the concrete subscriptions [subs] and
      arrivals [msgs] below ([..._refuted]);
    - [q + 1] keeps that property (the last delivery is still the newest:
      no glue can tell, since a callback emits no event and the last one
      wins), so it is refuted against the depth bound that the model
      proves of [rcl_deliverable] ([rcl_deliverable_depth]: a spin runs a
      callback at most [sub_queue] times, as a history of that depth holds
      no more);
    - through T2 itself, on the generated LandShark program: run in an
      environment that delivers what [oldest] or [q - 1] delivers (a ROS 1
      context whose arrivals are exactly those deliveries, which
      [deliverable] hands over unchanged: [sim_oldest], [sim_minus]), the
      node's trace is not a run of correct cycles for the real arrivals:
      the controller does not get the newest message ([DDC.newest]);
    - through T2 on the generated [Freshness.fresh] program (a timed GPS
      topic with a timeout, a fallback and derived inputs): run with the
      receipt times replaced by the cycle's time (a ROS 2 context that
      delivers the same messages in the same order, [sim_clock]), the
      node's trace is not a run of correct cycles for the real receipt
      times: the GPS clock's age ([DDC.newest_time], input [Gage]) is
      wrong. *)

From Coq Require Import String List ZArith Lia.
From ROSGen Require Import Errors Syntax Values Memory Environment Semantics Interp Interpproof
  NodeModel Wellformed Generator Generatorspec DDC Loopproof.
From ROSGenTests Require Import LandShark Mutants Freshness.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope list_scope.

(** ** The depth bound of the model *)

Lemma history_length:
  forall tn q msgs, length (history tn q msgs) = Nat.min q (count_topic tn msgs).
Proof.
  induction msgs as [|a rest IH]; simpl; [lia|].
  rewrite app_length, IH. unfold topic_eqb.
  destruct (string_dec (ar_topic a) tn); simpl.
  - destruct (Nat.ltb (count_topic tn rest) q) eqn:L; simpl;
      [apply Nat.ltb_lt in L|apply Nat.ltb_ge in L]; lia.
  - lia.
Qed.

(** One ROS 2 spin runs the callback of each of distinct subscriptions at
    most its depth times. *)
Lemma rcl_deliverable_depth:
  forall subs s msgs, NoDup subs -> In s subs ->
  (length (filter (of_sub s) (rcl_deliverable subs msgs)) <= sub_queue s)%nat.
Proof.
  intros subs s msgs N Hs. rewrite filter_rcl_deliverable by auto.
  unfold taken. rewrite map_length, history_length. lia.
Qed.

(** ** The mutants *)

Definition on_topic (tn : string) (msgs : list arrival) : list arrival :=
  filter (fun a => topic_eqb (ar_topic a) tn) msgs.

Definition with_history (h : subscription -> list arrival -> list arrival)
  (subs : list subscription) (msgs : list arrival) : list (subscription * arrival) :=
  flat_map (fun s => map (fun a => (s, a)) (h s msgs)) subs.

(** The take keeps the oldest [q]. *)
Definition oldest_deliverable : list subscription -> list arrival -> list (subscription * arrival) :=
  with_history (fun s msgs => firstn (sub_queue s) (on_topic (sub_topic s) msgs)).

(** Depth [q - 1], [q + 1]. *)
Definition minus_deliverable : list subscription -> list arrival -> list (subscription * arrival) :=
  with_history (fun s msgs => history (sub_topic s) (sub_queue s - 1) msgs).
Definition plus_deliverable : list subscription -> list arrival -> list (subscription * arrival) :=
  with_history (fun s msgs => history (sub_topic s) (S (sub_queue s)) msgs).

(** All the taken messages sorted on their receipt times (an insertion
    sort, stable). *)
Fixpoint insert_time (x : subscription * arrival) (l : list (subscription * arrival)) : list (subscription * arrival) :=
  match l with
  | [] => [x]
  | y :: r => if Z.ltb (ar_time (snd x)) (ar_time (snd y)) then x :: l else y :: insert_time x r
  end.

Definition sorted_deliverable (subs : list subscription) (msgs : list arrival) : list (subscription * arrival) :=
  fold_right insert_time [] (concat (map (fun s => taken s msgs) subs)).

(** The property of a delivery that T2's proof needs
    ([Main.last_delivered_rcl_deliverable]). *)
Definition keeps_newest (dl : list subscription -> list arrival -> list (subscription * arrival)) : Prop :=
  forall subs s msgs, NoDup subs -> In s subs -> (1 <= sub_queue s)%nat ->
  last_delivered s (dl subs msgs) = last_on (sub_topic s) msgs.

(** The depth bound the model proves ([rcl_deliverable_depth]). *)
Definition bounded_by_depth (dl : list subscription -> list arrival -> list (subscription * arrival)) : Prop :=
  forall subs s msgs, NoDup subs -> In s subs ->
  (length (filter (of_sub s) (dl subs msgs)) <= sub_queue s)%nat.

Example rcl_keeps_newest: keeps_newest rcl_deliverable.
Proof. exact last_delivered_rcl_deliverable. Qed.

Example rcl_bounded_by_depth: bounded_by_depth rcl_deliverable.
Proof. exact rcl_deliverable_depth. Qed.

(** ** A concrete spin *)

(** Two subscriptions: [/a] of depth 1, [/b] of depth 2.  Five arrivals;
    on [/b] the receipt times decrease (7 ns, then 6 ns). *)
Definition sa : subscription := mksub "/a" "T" 1 "cb_a".
Definition sb : subscription := mksub "/b" "T" 2 "cb_b".
Definition subs : list subscription := [sa; sb].

Definition arr (tn : string) (k t : Z) : arrival := mkarrival tn (MVscalar (Vint k)) t.

Definition msgs : list arrival :=
  [arr "/a" 1 5; arr "/b" 2 1; arr "/a" 3 3; arr "/b" 4 7; arr "/b" 5 6].

Lemma subs_nodup: NoDup subs.
Proof. repeat constructor; simpl; intuition discriminate. Qed.

(** What the wrapper delivers: [/a]'s newest, then [/b]'s newest two in
    take order (the head of [/b], 7 ns, is not earlier than [/a]'s 3 ns). *)
Example rcl_spin:
  rcl_deliverable subs msgs = [(sa, arr "/a" 3 3); (sb, arr "/b" 4 7); (sb, arr "/b" 5 6)].
Proof. reflexivity. Qed.

(** [oldest]: [/a]'s callback gets the first message, not the newest. *)
Example oldest_spin: last_delivered sa (oldest_deliverable subs msgs) = Some (arr "/a" 1 5).
Proof. reflexivity. Qed.

Theorem oldest_refuted: ~ keeps_newest oldest_deliverable.
Proof.
  intros K. specialize (K subs sa msgs subs_nodup (or_introl eq_refl) (le_n 1)).
  rewrite oldest_spin in K. discriminate.
Qed.

(** [q - 1]: a depth of 1 becomes 0, [/a]'s callback gets nothing. *)
Theorem depth_minus_one_refuted: ~ keeps_newest minus_deliverable.
Proof.
  intros K. specialize (K subs sa msgs subs_nodup (or_introl eq_refl) (le_n 1)).
  vm_compute in K. discriminate.
Qed.

(** [q + 1]: the newest still comes last, but [/b]'s callback runs 3
    times for a history of depth 2. *)
Example plus_keeps_the_last: last_delivered sb (plus_deliverable subs msgs) = last_on "/b" msgs.
Proof. reflexivity. Qed.

Theorem depth_plus_one_refuted: ~ bounded_by_depth plus_deliverable.
Proof.
  intros B. specialize (B subs sb msgs subs_nodup (or_intror (or_introl eq_refl))).
  vm_compute in B. lia.
Qed.

(** The sort: [/b]'s 6 ns message, taken last, runs before the 7 ns one,
    so the callback ends on the older message. *)
Example sorted_spin: last_delivered sb (sorted_deliverable subs msgs) = Some (arr "/b" 4 7).
Proof. reflexivity. Qed.

Theorem reorder_refuted: ~ keeps_newest sorted_deliverable.
Proof.
  intros K. specialize (K subs sb msgs subs_nodup (or_intror (or_introl eq_refl)) ltac:(simpl; lia)).
  rewrite sorted_spin in K. vm_compute in K. discriminate.
Qed.

(** ** Through T2: LandShark on ROS 2 *)

(** Spin 0: two messages on the left wheel (the second, [5.0], is the
    newest), one on the right wheel and one on the GPS. *)
Definition ls_arrivals (k : nat) : list arrival :=
  match k with
  | O => [mkarrival (tp_name left_wheel) (msg_x one) 1; mkarrival (tp_name right_wheel) (msg_x two) 2;
          mkarrival (tp_name gps) (msg_x three) 3; mkarrival (tp_name left_wheel) (msg_x five) 4]
  | _ => []
  end.

Definition ls_ctrl (_ : unit) (_ : mval) : unit * mval := (tt, MVstruct [("Out1", MVscalar four)]).

Definition ls_ctx : ros_context unit := mkctx ls_arrivals (fun _ => 0%Z) tt ls_ctrl Ros2.

Definition ls_subs : list subscription := subs_of landshark.

(** The generated program, run in [ls_ctx], does what T2 says. *)
Example ls_passes: check_in landshark ls_ctx 2000 landshark_prog 1 = true.
Proof. vm_compute. reflexivity. Qed.

(** A ROS 1 context whose arrivals are exactly what the mutant delivers
    for [ls_ctx] (queues of 1, one message per topic: [deliverable] hands
    them over as they are). *)
Definition sim_ctx (dl : list subscription -> list arrival -> list (subscription * arrival)) : ros_context unit :=
  mkctx (fun k => map snd (dl ls_subs (ls_arrivals k))) (fun _ => 0%Z) tt ls_ctrl Ros1.

Lemma sim_oldest: forall k, deliverable ls_subs (ctx_arrivals (sim_ctx oldest_deliverable) k)
                          = oldest_deliverable ls_subs (ctx_arrivals ls_ctx k).
Proof. intros [|k]; vm_compute; reflexivity. Qed.

Lemma sim_minus: forall k, deliverable ls_subs (ctx_arrivals (sim_ctx minus_deliverable) k)
                         = minus_deliverable ls_subs (ctx_arrivals ls_ctx k).
Proof. intros [|k]; vm_compute; reflexivity. Qed.

(** Run under the mutant's deliveries, the node's one cycle is not a
    correct cycle of [ls_ctx]: the left wheel's input is [1.0], not the
    newest [5.0] ([oldest]), or no input is the newest message
    ([q - 1]). *)
Theorem oldest_newest_refuted:
  exists t, program_behaves landshark_prog (sim_ctx oldest_deliverable) 1 t /\ ~ run_ok landshark ls_ctx 1 t.
Proof.
  destruct (run_trace 2000 landshark_prog (sim_ctx oldest_deliverable) 1) as [t|] eqn:R;
    [|vm_compute in R; discriminate].
  exists t. split; [exact (run_trace_sound _ _ _ _ _ _ R)|].
  intros OK. apply run_ok_okb in OK. vm_compute in R. inversion R; subst t. vm_compute in OK. discriminate.
Qed.

Theorem depth_minus_one_newest_refuted:
  exists t, program_behaves landshark_prog (sim_ctx minus_deliverable) 1 t /\ ~ run_ok landshark ls_ctx 1 t.
Proof.
  destruct (run_trace 2000 landshark_prog (sim_ctx minus_deliverable) 1) as [t|] eqn:R;
    [|vm_compute in R; discriminate].
  exists t. split; [exact (run_trace_sound _ _ _ _ _ _ R)|].
  intros OK. apply run_ok_okb in OK. vm_compute in R. inversion R; subst t. vm_compute in OK. discriminate.
Qed.

(** ** Through T2: the receipt time from the wrong clock *)

(** [Freshness.fctx] on ROS 2: the GPS messages arrive at 10, 80 and
    300 ms, the cycles end every 60 ms. *)
Definition fctx2 : ros_context unit :=
  mkctx (ctx_arrivals fctx) (ctx_time fctx) tt (ctx_step fctx) Ros2.

Example fresh_passes_ros2: check_in fresh fctx2 4000 fresh_prog 4 = true.
Proof. vm_compute. reflexivity. Qed.

(** The mutant's [ros_now] in a callback of spin [k]: the time of the
    cycle, [ctx_time k] (what [ros_now] answers outside callbacks during
    that spin), for every message. *)
Definition clock_ctx : ros_context unit :=
  mkctx (fun k => map (fun a => mkarrival (ar_topic a) (ar_msg a) (ctx_time fctx k)) (ctx_arrivals fctx k))
        (ctx_time fctx) tt (ctx_step fctx) Ros2.

(** The same messages to the same callbacks in the same order: only the
    receipt times differ. *)
Lemma sim_clock: forall k,
  map (fun sa => (fst sa, ar_msg (snd sa))) (rcl_deliverable (subs_of fresh) (ctx_arrivals clock_ctx k))
  = map (fun sa => (fst sa, ar_msg (snd sa))) (rcl_deliverable (subs_of fresh) (ctx_arrivals fctx2 k)).
Proof. intros [|[|[|[|k]]]]; vm_compute; reflexivity. Qed.

(** Run with the cycle's time as receipt time, the node's cycles are not
    correct for the real receipt times: in cycle 0 the GPS message is 60
    ms old by the mutant's clock, 50 ms by its receipt time. *)
Theorem receipt_clock_refuted:
  exists t, program_behaves fresh_prog clock_ctx 4 t /\ ~ run_ok fresh fctx2 4 t.
Proof.
  destruct (run_trace 4000 fresh_prog clock_ctx 4) as [t|] eqn:R; [|vm_compute in R; discriminate].
  exists t. split; [exact (run_trace_sound _ _ _ _ _ _ R)|].
  intros OK. apply run_ok_okb in OK. vm_compute in R. inversion R; subst t. vm_compute in OK. discriminate.
Qed.
