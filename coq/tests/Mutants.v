(** * The mutation catalogue: T2 rejects every plausible generator bug *)

(** Each mutant is the LandShark program ([LandShark.landshark_prog], the
    program [generate] computes for the paper's node) after a small
    transformation of its AST that a buggy generator could have made; for
    each, [~ node_ddc landshark p'] is proved: no buggy generator of this
    kind could have proved its theorem.

    The technique (after [DDCTeeth]): run the mutant with the interpreter
    in one concrete environment [ctx] (well-typed messages and
    controller, as [node_ddc] requires); T5 ([run_trace_sound]) makes the
    computed trace a behaviour of the mutant, so [node_ddc] would make it
    satisfy [run_ok]; but [run_okb], a computable necessary condition of
    [run_ok] ([run_ok_okb]), is [false] on it.  So a mutant is refuted by
    [refute] and one [vm_compute] ("The mutation catalogue" in
    coq/README.md: how to add one).

    The environment: before the first spin the left wheel reports
    [twist.linear.x = 1.0], the right wheel [2.0], the GPS [3.0]; before
    the second spin the left wheel reports [5.0]; the controller always
    outputs [Out1 = 4.0].  Runs have one cycle ([n = 1]), except for the
    mutant without [Controller_initialize], whose first step has no
    meaning (the environment has no controller state): it is run with
    zero cycles ([n = 0]), and its trace lacks [Einit].

    The generated program passes the same check ([p_passes]), as T2
    says it must. *)

From Coq Require Import String List ZArith Bool Lia.
From Flocq Require Import IEEE754.Binary IEEE754.Bits.
From ROSGen Require Import Errors Syntax Values Memory Environment Semantics Interp Interpproof.
From ROSGen Require Import FloatBits NodeModel Wellformed Generator DDC.
From ROSGen Require Copyproof.
From ROSGenTests Require Import LandShark.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope list_scope.

(** ** A computable necessary condition of [run_ok] *)

(** Equality of values, reflexive (floats compared by their bits). *)
Definition val_eqb (v w : val) : bool :=
  match v, w with
  | Vundef, Vundef => true
  | Vint a, Vint b | Vlong a, Vlong b => Z.eqb a b
  | Vsingle f, Vsingle g => Z.eqb (bits_of_b32 f) (bits_of_b32 g)
  | Vfloat f, Vfloat g => Z.eqb (bits_of_b64 f) (bits_of_b64 g)
  | Vptr b p, Vptr b' p' => Pos.eqb b b' && (if path_eq p p' then true else false)
  | Vfptr x, Vfptr y => String.eqb x y
  | _, _ => false
  end.

Lemma val_eqb_refl: forall v, val_eqb v v = true.
Proof.
  destruct v; simpl; try apply Z.eqb_refl; try apply String.eqb_refl; auto.
  rewrite Pos.eqb_refl. destruct (path_eq p p); auto.
Qed.

(** The scalar at path [p] of [mv]. *)
Definition scalar_at (mv : mval) (p : Values.path) : option val :=
  match mval_get mv p with Some (MVscalar v) => Some v | _ => None end.

Definition same_scalar (a b : option val) : bool :=
  match a, b with Some v, Some w => val_eqb v w | _, _ => false end.

(** Every input related to a topic holds the related field of the newest
    message of the topic, or its fallback if the topic is stale, and every
    derived input holds its value (the scalar part of [input_values]). *)
Definition inputs_okb {CS} (m : node_model) (ctx : ros_context CS) (i : nat) (u : mval) : bool :=
  forallb (fun ir =>
    existsb (fun tp => String.eqb (tp_cname tp) (ir_topic ir)
                       && match scalar_at (newest m ctx tp i) (path_steps (ir_path ir)) with
                          | Some v => same_scalar (Some (fed_value m ir v (newest_time m ctx tp i) (ctx_time ctx (S i))))
                                                  (scalar_at u (Sfield (ir_input ir) :: path_steps (ir_elem ir)))
                          | None => false
                          end)
            (subscribed m))
    (nm_inrels m)
  && forallb (fun dr =>
    existsb (fun tp => String.eqb (tp_cname tp) (dr_topic dr)
                       && same_scalar (Some (derived_value (dr_kind dr) (arrived m ctx tp i) (newest_time m ctx tp i)
                                                           (ctx_time ctx (S i))))
                                      (scalar_at u [Sfield (dr_input dr)]))
            (subscribed m))
    (nm_drels m).

(** Every field of a published message fed by an output relation, reached
    through no bounded sequence, holds the related output (the related
    part of [published_value], through [sent_scalar]). *)
Definition published_okb (m : node_model) (y : mval) (tp : topic) (mv : mval) : bool :=
  forallb (fun o => if String.eqb (or_topic o) (tp_cname tp)
                       && unbounded_path (composites m) (Tstruct (tp_msg tp)) (path_steps (or_path o))
                    then same_scalar (scalar_at y (Sfield (or_output o) :: path_steps (or_elem o)))
                                     (scalar_at mv (path_steps (or_path o)))
                    else true)
          (nm_outrels m).

(** The publications of one cycle, checked and consumed. *)
Fixpoint take_publishes (m : node_model) (y : mval) (tps : list topic) (t : trace) : option trace :=
  match tps, t with
  | [], _ => Some t
  | tp :: tps', Epublish name mv :: t' =>
      if String.eqb name (tp_name tp) && published_okb m y tp mv
      then take_publishes m y tps' t' else None
  | _, _ => None
  end.

(** [r] cycles from cycle [i]: a step on the right inputs, the
    publications, a sleep of the model's period; then nothing. *)
Fixpoint cycles_okb {CS} (m : node_model) (ctx : ros_context CS) (i r : nat) (t : trace) : bool :=
  match r, t with
  | O, [] => true
  | S r', Estep u y :: t1 =>
      inputs_okb m ctx i u
      && match take_publishes m y (published m) t1 with
         | Some (Esleep per :: t2) => Z.eqb per (nm_period_ms m) && cycles_okb m ctx (S i) r' t2
         | _ => false
         end
  | _, _ => false
  end.

(** Equality of start events (reflexive on them). *)
Definition start_eqb (e e' : event) : bool :=
  match e, e' with
  | Einit, Einit => true
  | Esubscribe a b q, Esubscribe a' b' q' | Eadvertise a b q, Eadvertise a' b' q' =>
      String.eqb a a' && String.eqb b b' && Nat.eqb q q'
  | _, _ => false
  end.

Fixpoint strip (l t : trace) : option trace :=
  match l, t with
  | [], _ => Some t
  | e :: l', e' :: t' => if start_eqb e e' then strip l' t' else None
  | _, _ => None
  end.

(** The start, then [n] cycles. *)
Definition run_okb {CS} (m : node_model) (ctx : ros_context CS) (n : nat) (t : trace) : bool :=
  match strip (start_events m) t with
  | Some t' => cycles_okb m ctx 0 n t'
  | None => false
  end.

Lemma strip_app:
  forall l t, Forall (fun e => start_eqb e e = true) l -> strip l (l ++ t) = Some t.
Proof.
  induction l as [|e l IH]; intros t F; simpl; auto.
  inversion F; subst. rewrite H1. auto.
Qed.

(** ** A computable consequence of T2 for a node that publishes one topic *)

(** [f y mv] checks what is sent in a cycle whose step gave the outputs
    [y] and whose one publication sent [mv]; [pub_okb f t] checks it for
    every cycle of the trace [t]. *)
Fixpoint pub_okb (f : mval -> mval -> bool) (t : trace) : bool :=
  match t with
  | Estep _ y :: Epublish _ mv :: t' => f y mv && pub_okb f t'
  | Estep _ _ :: _ => false
  | _ :: t' => pub_okb f t'
  | [] => true
  end.

Lemma pub_okb_skip:
  forall f e t, match e with Estep _ _ => False | _ => True end -> pub_okb f (e :: t) = pub_okb f t.
Proof. intros f [] t H; try contradiction; reflexivity. Qed.

Lemma pub_okb_start: forall f m t0, pub_okb f (start_events m ++ t0) = pub_okb f t0.
Proof.
  intros f m t0. unfold start_events. rewrite <- app_comm_cons, <- app_assoc, pub_okb_skip by exact I.
  induction (subscribed m) as [|a l IH]; cbn [map app].
  - induction (published m) as [|b l' IH']; cbn [map app]; [reflexivity|].
    rewrite pub_okb_skip by (unfold advertise_event; exact I). exact IH'.
  - rewrite pub_okb_skip by (unfold subscribe_event; exact I). exact IH.
Qed.

(** If [f] holds of every message [published_value] allows, as it is sent,
    then every run T2 allows passes [pub_okb f]: a program whose run fails
    it does not satisfy [node_ddc]. *)
Lemma run_ok_pub:
  forall CS m (ctx : ros_context CS) tp f n t,
  published m = [tp] -> controller_wt m ctx ->
  (forall y now g mv, mval_has_type (composites m) (Tstruct (nm_out_struct m)) y ->
     published_value m y now g tp mv -> f y (sent m tp mv) = true) ->
  run_ok m ctx n t -> pub_okb f t = true.
Proof.
  intros CS m ctx tp f n t Pub CW F (s & evs & _ & -> & C).
  rewrite pub_okb_start.
  assert (G: forall k i, (forall j, (i <= j < i + k)%nat -> cycle_ok m ctx j (s j) (evs j) (s (S j))) ->
             pub_okb f (concat (map evs (seq i k))) = true).
  { induction k as [|k IH]; intros i0 Ck; [reflexivity|].
    destruct (Ck i0 ltac:(lia)) as (u & y & mvs & E & _ & St & PV).
    cbn [seq map concat]. rewrite E, Pub. rewrite Pub in PV.
    inversion PV as [|tp' mv tps mvs' P Fa]; subst. inversion Fa; subst.
    assert (Ty: mval_has_type (composites m) (Tstruct (nm_out_struct m)) y).
    { generalize (CW (s i0) u). rewrite St. auto. }
    cbn [pub_okb publish_events map combine app fst snd]. rewrite (F y _ _ mv Ty P). cbn [andb].
    apply IH. intros j Hj. apply Ck. lia. }
  apply G. intros j Hj. apply C. lia.
Qed.

Lemma start_events_refl: forall m, Forall (fun e => start_eqb e e = true) (start_events m).
Proof.
  intros m. unfold start_events. constructor; [reflexivity|].
  apply Forall_app; split; apply Forall_forall; intros e H; apply in_map_iff in H;
    destruct H as (tp & <- & _); simpl; rewrite !String.eqb_refl, Nat.eqb_refl; reflexivity.
Qed.

Lemma take_publishes_ok:
  forall m y now g tps mvs rest, Forall2 (published_value m y now g) tps mvs ->
  take_publishes m y tps (publish_events m tps mvs ++ rest) = Some rest.
Proof.
  intros m y now g tps mvs rest F. induction F as [|tp mv tps mvs PV F IH]; simpl; auto.
  rewrite String.eqb_refl. simpl.
  replace (published_okb m y tp (sent m tp mv)) with true; [exact IH|].
  symmetry. apply forallb_forall. intros o Ho.
  destruct (String.eqb (or_topic o) (tp_cname tp)) eqn:E; [|reflexivity].
  destruct (unbounded_path (composites m) (Tstruct (tp_msg tp)) (path_steps (or_path o))) eqn:U;
    [|reflexivity]. simpl.
  apply String.eqb_eq in E. destruct PV as (T & Rel & _).
  destruct (Rel o Ho E) as (v & Gy & Gm).
  destruct (Copyproof.mval_get_typed_inv _ _ _ _ _ T Gm) as (t & Ty & _).
  unfold same_scalar, scalar_at. rewrite Gy, (sent_scalar m tp mv (or_path o) t v T U Ty Gm).
  apply val_eqb_refl.
Qed.

Lemma inputs_ok:
  forall CS m (ctx : ros_context CS) i u, input_values m ctx i u -> inputs_okb m ctx i u = true.
Proof.
  intros CS m ctx i u [_ [IV DV]]. unfold inputs_okb. apply andb_true_iff. split.
  - apply forallb_forall. intros ir Hir.
    destruct (IV ir Hir) as (tp & v & Htp & Ec & Gn & Gu).
    apply existsb_exists. exists tp. split; auto.
    rewrite Ec, String.eqb_refl. unfold scalar_at. rewrite Gn, Gu. apply val_eqb_refl.
  - apply forallb_forall. intros dr Hdr.
    destruct (DV dr Hdr) as (tp & Htp & Ec & Gu).
    apply existsb_exists. exists tp. split; auto.
    rewrite Ec, String.eqb_refl. unfold same_scalar, scalar_at. rewrite Gu. apply val_eqb_refl.
Qed.

Lemma cycles_ok_okb:
  forall CS m (ctx : ros_context CS) (s : nat -> CS) (evs : nat -> trace) r i,
  (forall j, (i <= j < i + r)%nat -> cycle_ok m ctx j (s j) (evs j) (s (S j))) ->
  cycles_okb m ctx i r (concat (map evs (seq i r))) = true.
Proof.
  intros CS m ctx s evs r. induction r as [|r IH]; intros i C; simpl; auto.
  destruct (C i ltac:(lia)) as (u & y & mvs & E & IV & _ & PV). rewrite E.
  simpl. rewrite (inputs_ok _ _ _ _ _ IV). simpl.
  rewrite <- app_assoc, (take_publishes_ok _ _ _ _ _ _ _ PV). simpl.
  rewrite Z.eqb_refl. simpl. apply IH. intros j Hj. apply C. lia.
Qed.

(** [run_okb] is a necessary condition of [run_ok]. *)
Theorem run_ok_okb:
  forall CS m (ctx : ros_context CS) n t, run_ok m ctx n t -> run_okb m ctx n t = true.
Proof.
  intros CS m ctx n t (s & evs & _ & Et & C). subst t. unfold run_okb.
  rewrite strip_app by apply start_events_refl.
  apply (cycles_ok_okb CS m ctx s evs n 0). intros j Hj. apply C. lia.
Qed.

(** ** The environment *)

Definition TS : type := Tstruct "geometry_msgs_TwistStamped".
Definition ce : composite_env := composites landshark.

Definition f64 (bits : Z) : val := Vfloat (float64_of_bits bits).
Definition one : val := f64 0x3FF0000000000000.
Definition two : val := f64 0x4000000000000000.
Definition three : val := f64 0x4008000000000000.
Definition four : val := f64 0x4010000000000000.
Definition five : val := f64 0x4014000000000000.

(** A [TwistStamped] that is zero except [twist.linear.x = x]. *)
Definition msg_x (x : val) : mval :=
  match mval_set (zero_mval ce TS) (path_steps twist_x) (MVscalar x) with
  | Some v => v
  | None => MVscalar Vundef
  end.

Definition ctx : ros_context unit :=
  mkctx (fun k => match k with
                  | O => [mkarrival (tp_name left_wheel) (msg_x one) 0;
                          mkarrival (tp_name right_wheel) (msg_x two) 0;
                          mkarrival (tp_name gps) (msg_x three) 0]
                  | 1%nat => [mkarrival (tp_name left_wheel) (msg_x five) 0]
                  | _ => []
                  end)
        (fun _ => 0%Z) tt (fun _ _ => (tt, MVstruct [("Out1", MVscalar four)])) Ros1.

Lemma ctx_arrivals_wt: arrivals_wt landshark ctx.
Proof.
  intros k a tp H Htp _. apply mval_typecheck_iff.
  simpl in Htp. destruct Htp as [<-|[<-|[<-|[]]]];
    destruct k as [|[|k]]; simpl in H; [| |contradiction| | |contradiction| | |contradiction];
    repeat destruct H as [H|H]; try contradiction; subst a; vm_compute; reflexivity.
Qed.

Lemma ctx_controller_wt: controller_wt landshark ctx.
Proof. intros s u. apply mval_typecheck_iff. vm_compute. reflexivity. Qed.

(** ** Refuting a mutant *)

(** The check of a program's run of [n] cycles in [ctx] against the
    model [m], with [fuel] steps of the interpreter ([true] when it runs
    out of fuel or the run is undefined: then nothing is refuted). *)
Definition check_in {CS} (m : node_model) (ctx : ros_context CS) (fuel : nat) (p : program) (n : nat) : bool :=
  match run_trace fuel p ctx n with
  | Some t => run_okb m ctx n t
  | None => true
  end.

(** A program whose run fails the check does not satisfy T2, in any
    context of well-typed arrivals and controller (every test node's
    mutants are refuted through this lemma). *)
Lemma refute_in {CS}:
  forall m (ctx : ros_context CS) fuel, arrivals_wt m ctx -> controller_wt m ctx ->
  forall p n, check_in m ctx fuel p n = false -> ~ node_ddc m p.
Proof.
  intros m ctx fuel AW CW p n H D. unfold check_in in H.
  destruct (run_trace fuel p ctx n) as [t|] eqn:R; [|discriminate].
  destruct (D CS ctx n AW CW) as [_ All].
  rewrite (run_ok_okb _ _ _ _ _ (All t (run_trace_sound _ ctx fuel p n t R))) in H. discriminate.
Qed.

Definition check : program -> nat -> bool := check_in landshark ctx 2000.

Lemma refute: forall p n, check p n = false -> ~ node_ddc landshark p.
Proof. exact (refute_in landshark ctx 2000 ctx_arrivals_wt ctx_controller_wt). Qed.

(** The generated program passes (as T2 says it must). *)
Example p_passes: check landshark_prog 0 = true /\ check landshark_prog 1 = true /\ check landshark_prog 2 = true.
Proof. vm_compute. auto. Qed.

(** ** Mutation tools *)

(** The definition named [x] replaced by [g] of it. *)
Definition on_def (x : ident) (g : globdef -> globdef) (p : program) : program :=
  mkprogram (prog_types p)
    (map (fun d => if string_dec (fst d) x then (fst d, g (snd d)) else d) (prog_defs p))
    (prog_main p).

(** The body of an internal function, the meaning of an external one. *)
Definition on_body (g : statement -> statement) (d : globdef) : globdef :=
  match d with
  | Gfun (Internal f) =>
      Gfun (Internal (mkfunction (fn_return f) (fn_params f) (fn_vars f) (fn_temps f) (g (fn_body f))))
  | _ => d
  end.

Definition on_ef (g : external_function -> external_function) (d : globdef) : globdef :=
  match d with Gfun (External ef ts t) => Gfun (External (g ef) ts t) | _ => d end.

(** A sequence [s1; ...; sn; skip] as the list [s1 ... sn], and back. *)
Fixpoint unseq (s : statement) : list statement :=
  match s with Ssequence a b => a :: unseq b | Sskip => [] | _ => [s] end.

Definition on_seq (g : list statement -> list statement) (s : statement) : statement :=
  seq_of (g (unseq s)).

(** The body of a loop [for (;;) { s1; ...; sn }]. *)
Definition on_loop (g : list statement -> list statement) (s : statement) : statement :=
  match s with Sloop b => Sloop (on_seq g b) | _ => s end.

(** List surgery. *)
Definition remove_nth (i : nat) (l : list statement) : list statement := firstn i l ++ skipn (S i) l.
Definition dup_nth (i : nat) (l : list statement) : list statement := firstn (S i) l ++ skipn i l.
Definition swap_next (i : nat) (l : list statement) : list statement :=
  match skipn i l with
  | a :: b :: rest => firstn i l ++ b :: a :: rest
  | _ => l
  end.

(** A copy [tmp = src; dst = tmp;] (the paper's Figure 14). *)
Definition on_copy_dst (g : expr -> expr) (s : statement) : statement :=
  match s with
  | Ssequence (Sset t src) (Sassign dst e) => Ssequence (Sset t src) (Sassign (g dst) e)
  | _ => s
  end.

(** [e.f] becomes [e.f'] (same type). *)
Definition rename_field (f f' : ident) (e : expr) : expr :=
  match e with Efield e1 g ty => if string_dec g f then Efield e1 f' ty else e | _ => e end.

(** The sources of the first two copies of a list exchanged. *)
Definition swap_sources (l : list statement) : list statement :=
  match l with
  | Ssequence (Sset t1 s1) a1 :: Ssequence (Sset t2 s2) a2 :: rest =>
      Ssequence (Sset t1 s2) a1 :: Ssequence (Sset t2 s1) a2 :: rest
  | _ => l
  end.

(** Every occurrence of the global [x] replaced by [y]. *)
Fixpoint subst_expr (x y : ident) (e : expr) : expr :=
  match e with
  | Evar z ty => Evar (if string_dec z x then y else z) ty
  | Ederef e1 ty => Ederef (subst_expr x y e1) ty
  | Eaddrof e1 ty => Eaddrof (subst_expr x y e1) ty
  | Efield e1 f ty => Efield (subst_expr x y e1) f ty
  | Eindex e1 e2 ty => Eindex (subst_expr x y e1) (subst_expr x y e2) ty
  | Ecast e1 ty => Ecast (subst_expr x y e1) ty
  | _ => e
  end.

Fixpoint subst_stmt (x y : ident) (s : statement) : statement :=
  match s with
  | Sassign a b => Sassign (subst_expr x y a) (subst_expr x y b)
  | Sset t a => Sset t (subst_expr x y a)
  | Ssequence a b => Ssequence (subst_stmt x y a) (subst_stmt x y b)
  | Sifthenelse c a b => Sifthenelse (subst_expr x y c) (subst_stmt x y a) (subst_stmt x y b)
  | Sloop a => Sloop (subst_stmt x y a)
  | _ => s
  end.

(** The program under mutation, and the names of its parts. *)
Definition p : program := landshark_prog.
Definition left_c : ident := tp_cname left_wheel.
Definition right_c : ident := tp_cname right_wheel.
Definition gps_c : ident := tp_cname gps.
Definition base_c : ident := tp_cname base.

(** Positions in [loop]'s body ([Generator.loop_stmts]): 0 [_ok = ros_ok()],
    1 the exit test, 2 [ros_spinOnce()], 3 [input_glue()], 4 the step,
    5 [output_glue_base(&cmd)], 6 [ros_publish_base(&cmd)], 7
    [ros_rate_sleep()].  In [main]'s ([Generator.main_stmts]): 0
    [ros_init()], 1 [Controller_initialize()], 2-4 the subscriptions, 5
    the advertisement, 6 [loop()], 7 [return 0]. *)

(** ** The catalogue *)

(** (a) [In1] and [In2] read each other's topic ([DDCTeeth]'s mutant). *)
Definition m_swapped_sources : program := on_def input_glue_name (on_body (on_seq swap_sources)) p.
Theorem swapped_sources_refuted: ~ node_ddc landshark m_swapped_sources.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (b) [main] does not call [Controller_initialize()]: with cycles, the
    first step is undefined; without, the trace lacks [Einit]. *)
Definition m_no_initialize : program := on_def main_name (on_body (on_seq (remove_nth 1))) p.
Theorem no_initialize_refuted: ~ node_ddc landshark m_no_initialize.
Proof. apply (refute _ 0). vm_compute. reflexivity. Qed.

(** (c) A subscription with queue size [q + 1]. *)
Definition m_subscribe_queue : program :=
  on_def (subscribe_name gps_c)
    (on_ef (fun ef => match ef with EF_ros_subscribe t ty q => EF_ros_subscribe t ty (S q) | _ => ef end)) p.
Theorem subscribe_queue_refuted: ~ node_ddc landshark m_subscribe_queue.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (d) An advertisement with queue size [q + 1]. *)
Definition m_advertise_queue : program :=
  on_def (advertise_name base_c)
    (on_ef (fun ef => match ef with EF_ros_advertise t ty q => EF_ros_advertise t ty (S q) | _ => ef end)) p.
Theorem advertise_queue_refuted: ~ node_ddc landshark m_advertise_queue.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (e) [ros_rate_sleep] with another period (25 ms instead of 20). *)
Definition m_wrong_period : program :=
  on_def ros_rate_sleep_name
    (on_ef (fun ef => match ef with EF_ros_rate_sleep per => EF_ros_rate_sleep (per + 5) | _ => ef end)) p.
Theorem wrong_period_refuted: ~ node_ddc landshark m_wrong_period.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (f) [input_glue] skips the copy of [In3] (the GPS): [In3] stays 0. *)
Definition m_skipped_copy : program := on_def input_glue_name (on_body (on_seq (remove_nth 2))) p.
Theorem skipped_copy_refuted: ~ node_ddc landshark m_skipped_copy.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (g) The output glue copies [Out1] into [twist.linear.y] instead of
    [twist.linear.x]. *)
Definition m_wrong_output_field : program :=
  on_def (output_glue_name base_c)
    (on_body (fun s => match s with
                       | Ssequence (Ssequence zero copies) strs =>
                           Ssequence (Ssequence zero (on_seq (map (on_copy_dst (rename_field "x" "y"))) copies)) strs
                       | _ => s
                       end)) p.
Theorem wrong_output_field_refuted: ~ node_ddc landshark m_wrong_output_field.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (h) [loop] does not call [ros_spinOnce()]: no message is ever
    delivered. *)
Definition m_no_spin : program := on_def loop_name (on_body (on_loop (remove_nth 2))) p.
Theorem no_spin_refuted: ~ node_ddc landshark m_no_spin.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (i) [loop] calls [ros_spinOnce()] twice: cycle 0 sees the left
    wheel's message of spin 1 ([5.0]) instead of [1.0]. *)
Definition m_double_spin : program := on_def loop_name (on_body (on_loop (dup_nth 2))) p.
Theorem double_spin_refuted: ~ node_ddc landshark m_double_spin.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (j) [input_glue()] before [ros_spinOnce()]: the controller sees the
    previous cycle's messages (zero in cycle 0). *)
Definition m_glue_before_spin : program := on_def loop_name (on_body (on_loop (swap_next 2))) p.
Theorem glue_before_spin_refuted: ~ node_ddc landshark m_glue_before_spin.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (k) Output glue and publication before the step (the step moved
    after them): the cycle publishes before it steps. *)
Definition m_publish_before_step : program :=
  on_def loop_name (on_body (on_loop (fun l => swap_next 5 (swap_next 4 l)))) p.
Theorem publish_before_step_refuted: ~ node_ddc landshark m_publish_before_step.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (l) The left wheel's callback writes the right wheel's global. *)
Definition m_callback_wrong_global : program :=
  on_def (callback_name left_c) (on_body (subst_stmt (msg_var left_c) (msg_var right_c))) p.
Theorem callback_wrong_global_refuted: ~ node_ddc landshark m_callback_wrong_global.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (m) A subscription to another topic name ([/landshark/gps] instead of
    [/landshark/gps_velocity]). *)
Definition m_wrong_topic : program :=
  on_def (subscribe_name gps_c)
    (on_ef (fun ef => match ef with EF_ros_subscribe _ ty q => EF_ros_subscribe "/landshark/gps" ty q
                                    | _ => ef end)) p.
Theorem wrong_topic_refuted: ~ node_ddc landshark m_wrong_topic.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (n) An advertisement of another message struct (the wrapper would
    advertise one type and publish another). *)
Definition m_advertise_struct : program :=
  on_def (advertise_name base_c)
    (on_ef (fun ef => match ef with EF_ros_advertise t _ q => EF_ros_advertise t "geometry_msgs_Twist" q
                                    | _ => ef end)) p.
Theorem advertise_struct_refuted: ~ node_ddc landshark m_advertise_struct.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (c1) The left wheel's callback copies nothing: a generator whose
    [read_paths] forgot the topic's input relations.  [In1] stays 0. *)
Definition m_callback_no_copy : program :=
  on_def (callback_name left_c) (on_body (fun _ => Sskip)) p.
Theorem callback_no_copy_refuted: ~ node_ddc landshark m_callback_no_copy.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (c2) The left wheel's callback copies the leaves the node does not
    read, and not the one it reads (the filter of [read_leaves]
    inverted). *)
Definition unread_copies : statement :=
  seq_of (map (leaf_copy ce (Evar (msg_var left_c) TS) (deref_param msg_param "geometry_msgs_TwistStamped"))
              (filter (fun l => negb (is_read landshark left_c (fst l)))
                      (leaves (nm_msgs landshark) "geometry_msgs_TwistStamped"))).
Definition m_callback_unread_leaves : program :=
  on_def (callback_name left_c)
    (fun d => match d with
              | Gfun (Internal f) =>
                  Gfun (Internal (mkfunction (fn_return f) (fn_params f) (fn_vars f)
                                   [(temp_name Puint32, Tint I32 Unsigned); (temp_name Pfloat64, Tfloat F64)]
                                   unread_copies))
              | _ => d
              end) p.
Theorem callback_unread_leaves_refuted: ~ node_ddc landshark m_callback_unread_leaves.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.
