(** * Freshness (rule 4.12): the generator, the interpreter, and mutants *)

(** [fresh] is LandShark with clocks: the GPS topic has a 100 ms
    timeout, and its input [In3] falls back to [7.0] while it is stale;
    the left wheel has a 100 ms timeout and holds its last value; the GPS
    feeds three derived inputs ([Gnew], [Grcvd], [Gage]) and the right
    wheel, on which nothing ever arrives, feeds [Rage].  [generate]
    accepts it and refuses bad freshness naming the culprit; the
    interpreter runs it in an environment where the GPS message is fresh,
    stale, exactly as old as the timeout, and newer than the cycle (the
    clock went back); the inputs are what T2 says; and four mutants of
    the freshness code are refuted against T2 (with [Mutants.run_okb],
    whose input check covers fallbacks and derived inputs). *)

From Coq Require Import String List ZArith Lia.
From Flocq Require Import IEEE754.Binary IEEE754.Bits.
From ROSGen Require Import FloatBits Errors Syntax Values Memory Environment Semantics Interp Interpproof
  NodeModel Wellformed Generator Generatorspec DDC Loopproof.
From ROSGenTests Require Import LandShark Mutants.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope list_scope.

Definition seven : val := f64 0x401C000000000000.

Definition gps_c : ident := "landshark_gps_velocity".
Definition left_c : ident := "landshark_left_wheel_velocity".
Definition right_c : ident := "landshark_right_wheel_velocity".

Definition with_fresh (timeouts : list (ident * Z)) (fallbacks : list (ident * val)) (drels : list drel)
                      (inputs : list (ident * ftype)) : node_model :=
  reshape landshark (nm_inputs landshark ++ inputs) (nm_msgs landshark) timeouts fallbacks drels [] [] [].

Definition derived_inputs : list (ident * ftype) :=
  [("Gnew", FTprim Pbool); ("Grcvd", FTprim Pbool); ("Gage", FTprim Puint32); ("Rage", FTprim Puint32)].

Definition derived_rels : list drel :=
  [mkdrel gps_c Dis_new "Gnew"; mkdrel gps_c Dreceived "Grcvd"; mkdrel gps_c Dage_ms "Gage";
   mkdrel right_c Dage_ms "Rage"].

Definition fresh : node_model :=
  with_fresh [(gps_c, 100%Z); (left_c, 100%Z)] [("In3", seven)] derived_rels derived_inputs.

(** ** The generator *)

Example fresh_wf: wf fresh = true.
Proof. vm_compute. reflexivity. Qed.

Definition fresh_result : res program := Eval vm_compute in generate fresh.
Definition fresh_prog : program :=
  Eval vm_compute in match fresh_result with OK p => p | Error _ => mkprogram [] [] "" end.

Lemma fresh_generates: generate fresh = OK fresh_prog.
Proof. vm_compute. reflexivity. Qed.

(** [ros_now] and the clocks are declared, and only by a node with a
    timed topic; the right wheel is timed (it has a derived input). *)
Example clocks_declared:
  find_def fresh_prog "ros_now" = Some (Gfun (External EF_ros_now [] (Tlong Unsigned)))
  /\ find_def fresh_prog "landshark_gps_velocity_time" = Some (Gvar (Tlong Unsigned))
  /\ find_def fresh_prog "landshark_right_wheel_velocity_rcvd" = Some (Gvar (Tint I8 Unsigned))
  /\ find_def landshark_prog "ros_now" = None.
Proof. vm_compute. repeat split; reflexivity. Qed.

Example refuse_timeout_published:
  refused (with_fresh [("landshark_control_base_velocity", 100%Z)] [] [] [])
    "Generator: bad timeout (rule 4.12) on topic 'landshark_control_base_velocity': 100 ms must be on a subscribed topic, from the period to 86400000 ms".
Proof. vm_compute. reflexivity. Qed.

Example refuse_timeout_too_long:
  refused (with_fresh [(gps_c, 86400001%Z)] [] [] [])
    "Generator: bad timeout (rule 4.12) on topic 'landshark_gps_velocity': 86400001 ms must be on a subscribed topic, from the period to 86400000 ms".
Proof. vm_compute. reflexivity. Qed.

(** A fallback of the wrong type, or for an input whose topic has no
    timeout. *)
Example refuse_fallback_type:
  refused (with_fresh [(gps_c, 100%Z)] [("In3", Vint 7)] [] [])
    "Generator: bad fallback (rule 4.12) for controller input 'In3': it must be a value of the input's type, for an input fed by a topic with a timeout".
Proof. vm_compute. reflexivity. Qed.

Example refuse_fallback_no_timeout:
  refused (with_fresh [] [("In3", seven)] [] [])
    "Generator: bad fallback (rule 4.12) for controller input 'In3': it must be a value of the input's type, for an input fed by a topic with a timeout".
Proof. vm_compute. reflexivity. Qed.

(** [is_new] into a [uint32] input. *)
Example refuse_derived_type:
  refused (with_fresh [] [] [mkdrel gps_c Dis_new "Gage"] [("Gage", FTprim Puint32)])
    "Generator: bad derived input (rule 4.12) 'Gage': it must be of topic 'landshark_gps_velocity', subscribed, and feed a controller input of its type (bool, or uint32 for age_ms)".
Proof. vm_compute. reflexivity. Qed.

(** An input fed by two derived inputs. *)
Example refuse_fed_twice:
  refused (with_fresh [] [] [mkdrel gps_c Dis_new "Gnew"; mkdrel left_c Dreceived "Gnew"] [("Gnew", FTprim Pbool)])
    "Generator: controller input fed by several input relations: 'Gnew'".
Proof. vm_compute. reflexivity. Qed.

(** ** A run with known times *)

(** Cycle [i] is read at [60 (i + 1)] ms.  The GPS message [1.0] arrives
    at 10 ms (for cycle 0: 50 ms old then, fresh; 110 ms old in cycle 1,
    stale); [2.0] at 80 ms (for cycle 2, read at 180 ms: exactly 100 ms
    old, fresh); [3.0] at 300 ms (for cycle 3, read at 240 ms: the clock
    went back, age 0).  The left wheel's [5.0] arrives at 0 ns (stale
    from cycle 1 on: it holds its value).  Nothing arrives on the right
    wheel. *)
Definition ms (n : Z) : Z := n * 1000000.

Definition fctx : ros_context unit :=
  mkctx (fun k => match k with
                  | O => [mkarrival (tp_name left_wheel) (msg_x five) 0; mkarrival (tp_name gps) (msg_x one) (ms 10)]
                  | 2%nat => [mkarrival (tp_name gps) (msg_x two) (ms 80)]
                  | 3%nat => [mkarrival (tp_name gps) (msg_x three) (ms 300)]
                  | _ => []
                  end)
        (fun k => ms (60 * Z.of_nat k)) tt (fun _ _ => (tt, MVstruct [("Out1", MVscalar four)])) Ros1.

Lemma fctx_arrivals_wt: arrivals_wt fresh fctx.
Proof.
  intros k a tp H Htp _. apply mval_typecheck_iff.
  simpl in Htp. destruct Htp as [<-|[<-|[<-|[]]]];
    destruct k as [|[|[|[|k]]]]; simpl in H; repeat destruct H as [H|H]; try contradiction;
    subst a; vm_compute; reflexivity.
Qed.

Lemma fctx_controller_wt: controller_wt fresh fctx.
Proof. intros s u. apply mval_typecheck_iff. vm_compute. reflexivity. Qed.

(** The inputs of the controller's steps in a trace. *)
Definition inputs_of (t : trace) : list mval :=
  flat_map (fun e => match e with Estep u _ => [u] | _ => [] end) t.

Definition run4 : option trace := Eval vm_compute in run_trace 4000 fresh_prog fctx 4.

(** In1 holds 5.0 (hold), In3 is the GPS value when fresh, 7.0 when
    stale; Gnew, Grcvd, Gage (ms) and Rage as the times say. *)
Example fresh_run:
  match run4 with
  | Some t =>
      map (fun u => (scalar_at u [Sfield "In1"], scalar_at u [Sfield "In3"], scalar_at u [Sfield "Gnew"],
                     scalar_at u [Sfield "Grcvd"], scalar_at u [Sfield "Gage"], scalar_at u [Sfield "Rage"]))
          (inputs_of t)
      = [(Some five, Some one, Some (Vint 1), Some (Vint 1), Some (Vint 50), Some (Vint 4294967295));
         (Some five, Some seven, Some (Vint 0), Some (Vint 1), Some (Vint 110), Some (Vint 4294967295));
         (Some five, Some two, Some (Vint 1), Some (Vint 1), Some (Vint 100), Some (Vint 4294967295));
         (Some five, Some three, Some (Vint 1), Some (Vint 1), Some (Vint 0), Some (Vint 4294967295))]
  | None => False
  end.
Proof. vm_compute. reflexivity. Qed.

(** ** Mutants *)

Definition fcheck : program -> nat -> bool := check_in fresh fctx 4000.

Lemma frefute: forall p n, fcheck p n = false -> ~ node_ddc fresh p.
Proof. exact (refute_in fresh fctx 4000 fctx_arrivals_wt fctx_controller_wt). Qed.

(** The generated program passes (as T2 says it must). *)
Example fresh_passes: fcheck fresh_prog 4 = true.
Proof. vm_compute. reflexivity. Qed.

(** A statement changed everywhere in [input_glue] by [g]. *)
Fixpoint map_stmt (g : statement -> statement) (s : statement) : statement :=
  match s with
  | Ssequence a b => g (Ssequence (map_stmt g a) (map_stmt g b))
  | Sifthenelse c a b => g (Sifthenelse c (map_stmt g a) (map_stmt g b))
  | _ => g s
  end.

Definition on_input_glue (g : statement -> statement) (p : program) : program :=
  on_def "input_glue" (on_body (map_stmt g)) p.

(** (f1) the timeout off by one: stale when [age >= timeout]. *)
Definition m_timeout_off_by_one : program :=
  on_input_glue (fun s => match s with
                          | Sifthenelse (Ebinop Olt a b ty) s1 s2 => Sifthenelse (Ebinop Ole a b ty) s1 s2
                          | _ => s
                          end) fresh_prog.
Theorem m_timeout_off_by_one_refuted: ~ node_ddc fresh m_timeout_off_by_one.
Proof. apply (frefute _ 3). vm_compute. reflexivity. Qed.

(** (f2) [is_new] not reset: the flags are never cleared. *)
Definition m_new_not_reset : program :=
  on_input_glue (fun s => match s with
                          | Sassign (Evar x ty) (Econst_int 0 ty') =>
                              if string_dec x "landshark_gps_velocity_new" then Sskip else s
                          | _ => s
                          end) fresh_prog.
Theorem m_new_not_reset_refuted: ~ node_ddc fresh m_new_not_reset.
Proof. apply (frefute _ 2). vm_compute. reflexivity. Qed.

(** (f3) the fallback left out: a stale input keeps the old value. *)
Definition m_no_fallback : program :=
  on_input_glue (fun s => match s with
                          | Sifthenelse (Ebinop Olt a b ty) _ s2 => Sifthenelse (Ebinop Olt a b ty) Sskip s2
                          | _ => s
                          end) fresh_prog.
Theorem m_no_fallback_refuted: ~ node_ddc fresh m_no_fallback.
Proof. apply (frefute _ 2). vm_compute. reflexivity. Qed.

(** (f4) a clock that went back not handled: the age is [now - time],
    wrapped around. *)
Definition m_age_wraps : program :=
  on_input_glue (fun s => match s with
                          | Sifthenelse (Ebinop Ole a b ty) s1 s2 =>
                              match a with
                              | Evar _ _ => s1
                              | _ => s
                              end
                          | _ => s
                          end) fresh_prog.
Theorem m_age_wraps_refuted: ~ node_ddc fresh m_age_wraps.
Proof. apply (frefute _ 4). vm_compute. reflexivity. Qed.

(** (f5) the age of another topic: the right wheel's [age_ms] computed
    from the GPS clock. *)
Fixpoint rename_var (x x' : ident) (e : expr) : expr :=
  match e with
  | Evar y ty => Evar (if string_dec y x then x' else y) ty
  | Ebinop op a b ty => Ebinop op (rename_var x x' a) (rename_var x x' b) ty
  | _ => e
  end.

Definition m_age_other_topic : program :=
  on_input_glue (fun s => match s with
                          | Sifthenelse c s1 s2 =>
                              Sifthenelse (rename_var "landshark_right_wheel_velocity_rcvd" "landshark_gps_velocity_rcvd"
                                             (rename_var "landshark_right_wheel_velocity_time" "landshark_gps_velocity_time" c))
                                          s1 s2
                          | Sset x e => Sset x (rename_var "landshark_right_wheel_velocity_time" "landshark_gps_velocity_time" e)
                          | _ => s
                          end) fresh_prog.
Theorem m_age_other_topic_refuted: ~ node_ddc fresh m_age_other_topic.
Proof. apply (frefute _ 1). vm_compute. reflexivity. Qed.
