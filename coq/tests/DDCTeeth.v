(** * The DDC specification has teeth *)

(** [node_ddc] (theorem T2's statement) is not vacuous: on the LandShark
    node of the paper's Table 1, the program [p'] obtained from the
    generated program [p] by swapping the sources of [In1] and [In2] in
    [input_glue] does not satisfy it.  The witness: one cycle, the left
    wheel reports [0.0] and the right wheel [+inf] before the first spin,
    and the controller outputs [+inf].  The interpreter computes the run
    of [p'] (T5 makes it a behaviour, determinism the only one), and its
    step (after the start: [Einit], the subscriptions, the advertisement)
    hands [In1 = +inf] to the controller instead of the left wheel's
    [0.0].

    For the generated [p], the same run satisfies [run_ok], both by T2
    and by a direct check.  [Mutants] extends this to a catalogue of
    generator bugs, with a generic refutation. *)

From Coq Require Import String List ZArith.
From Flocq Require Import IEEE754.Binary.
From ROSGen Require Import Errors Syntax Values Memory Environment Semantics Interp Interpproof.
From ROSGen Require Import NodeModel Wellformed Generator Generatorspec Generatorproof DDC Loopproof.
From ROSGenTests Require Import LandShark.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope list_scope.

(** ** The LandShark program ([LandShark]) *)

Definition p : program := landshark_prog.

Lemma p_generated: generate landshark = OK p.
Proof. vm_compute. reflexivity. Qed.

(** ** The mutant: [In1] and [In2] read each other's topic *)

(** Swap the sources of the first two copies of a body
    [tmp = src1; In1 = tmp; tmp = src2; In2 = tmp; ...]. *)
Definition swap_first_sources (s : statement) : statement :=
  match s with
  | Ssequence (Ssequence (Sset t1 src1) a1) (Ssequence (Ssequence (Sset t2 src2) a2) rest) =>
      Ssequence (Ssequence (Sset t1 src2) a1) (Ssequence (Ssequence (Sset t2 src1) a2) rest)
  | _ => s
  end.

Definition mutate (d : ident * globdef) : ident * globdef :=
  match d with
  | (x, Gfun (Internal f)) =>
      if string_dec x input_glue_name
      then (x, Gfun (Internal (mkfunction (fn_return f) (fn_params f) (fn_vars f) (fn_temps f)
                                          (swap_first_sources (fn_body f)))))
      else d
  | _ => d
  end.

Definition p' : program := mkprogram (prog_types p) (map mutate (prog_defs p)) (prog_main p).

(** The mutation is exactly the swap: [In1] now reads the right wheel and
    [In2] the left wheel; nothing else changed. *)
Definition TS : type := Tstruct "geometry_msgs_TwistStamped".

Definition twist_x_of (e : expr) : expr :=
  Efield (Efield (Efield e "twist" (Tstruct "geometry_msgs_Twist"))
                 "linear" (Tstruct "geometry_msgs_Vector3"))
         "x" tdouble.

Definition input_copy_of (g In : ident) : statement :=
  Ssequence (Sset "_t_double" (twist_x_of (Evar g TS)))
            (Sassign (Efield (Evar "Controller_U" (Tstruct "ExtU_Controller_T")) In tdouble)
                     (Etempvar "_t_double" tdouble)).

Example p_input_glue:
  find_def p input_glue_name = Some (Gfun (Internal (mkfunction Tvoid [] [] [("_t_double", tdouble)]
    (Ssequence (input_copy_of "landshark_left_wheel_velocity_msg" "In1")
    (Ssequence (input_copy_of "landshark_right_wheel_velocity_msg" "In2")
    (Ssequence (input_copy_of "landshark_gps_velocity_msg" "In3") Sskip)))))).
Proof. vm_compute. reflexivity. Qed.

Example p'_input_glue:
  find_def p' input_glue_name = Some (Gfun (Internal (mkfunction Tvoid [] [] [("_t_double", tdouble)]
    (Ssequence (input_copy_of "landshark_right_wheel_velocity_msg" "In1")
    (Ssequence (input_copy_of "landshark_left_wheel_velocity_msg" "In2")
    (Ssequence (input_copy_of "landshark_gps_velocity_msg" "In3") Sskip)))))).
Proof. vm_compute. reflexivity. Qed.

Lemma mutate_other: forall d, fst d <> input_glue_name -> mutate d = d.
Proof.
  intros [y g] N. simpl in N. destruct g as [[f|ef targs tres]|ty]; simpl; auto.
  destruct (string_dec y input_glue_name); [contradiction|auto].
Qed.

Lemma find_assoc_mutate:
  forall l x, x <> input_glue_name -> find_assoc x (map mutate l) = find_assoc x l.
Proof.
  induction l as [|[y g] l IH]; intros x N; [reflexivity|].
  change (map mutate ((y, g) :: l)) with (mutate (y, g) :: map mutate l).
  assert (M: fst (mutate (y, g)) = y /\ (y <> input_glue_name -> snd (mutate (y, g)) = g)).
  { destruct g as [[f|ef targs tres]|ty]; unfold mutate; auto.
    destruct (string_dec y input_glue_name); simpl; split; auto; intros C; contradiction. }
  destruct (mutate (y, g)) as [y' g'] eqn:E. simpl in M. destruct M as [-> M].
  simpl. destruct (string_dec x y) as [->|Nxy].
  - rewrite M; auto.
  - apply IH; auto.
Qed.

Example p'_same_elsewhere:
  forall x, x <> input_glue_name -> find_def p' x = find_def p x.
Proof. intros x N. unfold find_def, p'. cbn [prog_defs]. apply find_assoc_mutate; auto. Qed.

(** ** The environment *)

Definition f_zero : float64 := B754_zero 53 1024 false.
Definition f_inf : float64 := B754_infinity 53 1024 false.

Definition ce : composite_env := composites landshark.

(** A [TwistStamped] that is zero except [twist.linear.x = x]. *)
Definition msg_x (x : float64) : mval :=
  match mval_set (zero_mval ce TS) (path_steps twist_x) (MVscalar (Vfloat x)) with
  | Some v => v
  | None => MVscalar Vundef
  end.

(** The controller's outputs: [Out1 = +inf]. *)
Definition y_out : mval := MVstruct [("Out1", MVscalar (Vfloat f_inf))].

(** Before the first spin, the left wheel reports [0.0] and the right
    wheel [+inf]; nothing else ever arrives.  The controller always
    outputs [Out1 = +inf]. *)
Definition ctx : ros_context unit :=
  mkctx (fun k => match k with
                  | O => [mkarrival (tp_name left_wheel) (msg_x f_zero) 0; mkarrival (tp_name right_wheel) (msg_x f_inf) 0]
                  | S _ => []
                  end)
        (fun _ => 0%Z) tt (fun _ _ => (tt, y_out)) Ros1.

Lemma ctx_arrivals_wt: arrivals_wt landshark ctx.
Proof.
  intros k a tp H Htp E. destruct k as [|k]; simpl in H; [|contradiction].
  simpl in Htp. apply mval_typecheck_iff.
  destruct H as [H|[H|[]]]; subst a;
    destruct Htp as [<-|[<-|[<-|[]]]]; simpl in E; try discriminate E; vm_compute; reflexivity.
Qed.

Lemma ctx_controller_wt: controller_wt landshark ctx.
Proof. intros s u. apply mval_typecheck_iff. vm_compute. reflexivity. Qed.

(** ** The run of the mutant *)

Definition t' : trace :=
  match run_trace 1000 p' ctx 1 with Some t => t | None => [] end.

Lemma p'_behaves: program_behaves p' ctx 1 t'.
Proof. apply run_trace_sound with (fuel := 1000%nat). vm_compute. reflexivity. Qed.

(** Its first step (after the start: [Einit], three subscriptions, one
    advertisement) hands the controller [In1 = +inf], [In2 = 0.0]. *)
Example t'_first_inputs:
  match skipn 5 t' with
  | Estep u _ :: _ => mval_get u [Sfield "In1"] = Some (MVscalar (Vfloat f_inf))
                      /\ mval_get u [Sfield "In2"] = Some (MVscalar (Vfloat f_zero))
  | _ => False
  end.
Proof. vm_compute. split; reflexivity. Qed.

(** The newest left-wheel message of cycle 0 has [twist.linear.x = 0.0]. *)
Example newest_left:
  mval_get (newest landshark ctx left_wheel 0) (path_steps twist_x) = Some (MVscalar (Vfloat f_zero)).
Proof. vm_compute. reflexivity. Qed.

Theorem mutant_not_ddc: ~ node_ddc landshark p'.
Proof.
  intros D.
  destruct (D unit ctx 1%nat ctx_arrivals_wt ctx_controller_wt) as [_ All].
  destruct (All t' p'_behaves) as (s & evs & _ & Et & C).
  destruct (C O (le_n 1)) as (u & y & mvs & Ee & [_ [IV _]] & _ & _).
  change (concat (map evs (seq 0 1))) with (evs O ++ []) in Et.
  rewrite app_nil_r, Ee in Et.
  assert (Hu: mval_get u [Sfield "In1"] = Some (MVscalar (Vfloat f_inf))).
  { generalize t'_first_inputs. rewrite Et. intros [H _]. exact H. }
  destruct (IV (mkinrel "landshark_left_wheel_velocity" twist_x "In1")) as (tp & v & Htp & Ec & Gn & Gu).
  { simpl; auto. }
  simpl in Htp. destruct Htp as [<-|[<-|[<-|[]]]]; try discriminate Ec.
  simpl ir_path in Gn. rewrite newest_left in Gn. simpl ir_input in Gu. simpl ir_elem in Gu.
  change (path_steps []) with (@nil step) in Gu. rewrite Hu in Gu.
  unfold fed_value, stale, timeout_ns in Gu. simpl in Gu.
  rewrite <- Gu in Gn. unfold f_zero, f_inf in Gn. discriminate Gn.
Qed.

(** ** The generated program on the same environment *)

Definition t : trace :=
  match run_trace 1000 p ctx 1 with Some t => t | None => [] end.

Lemma p_behaves: program_behaves p ctx 1 t.
Proof. apply run_trace_sound with (fuel := 1000%nat). vm_compute. reflexivity. Qed.

(** By T2. *)
Theorem p_run_ok: run_ok landshark ctx 1 t.
Proof.
  destruct (Loopproof.generate_node_ddc landshark p p_generated unit ctx 1%nat
              ctx_arrivals_wt ctx_controller_wt) as [_ All].
  apply All, p_behaves.
Qed.

(** Concretely: the one cycle steps the controller on [In1 = 0.0] (left
    wheel), [In2 = +inf] (right wheel), [In3 = 0.0] (no GPS message yet),
    then publishes a zero message whose [twist.linear.x] is [Out1 = +inf],
    then ends. *)
Definition u_expected : mval :=
  MVstruct [("In1", MVscalar (Vfloat f_zero)); ("In2", MVscalar (Vfloat f_inf));
            ("In3", MVscalar (Vfloat f_zero))].

Definition start_expected : trace :=
  [Einit;
   Esubscribe "/landshark/left_wheel_velocity" "geometry_msgs_TwistStamped" 1;
   Esubscribe "/landshark/right_wheel_velocity" "geometry_msgs_TwistStamped" 1;
   Esubscribe "/landshark/gps_velocity" "geometry_msgs_TwistStamped" 1;
   Eadvertise "/landshark_control/base_velocity" "geometry_msgs_TwistStamped" 1].

Definition cycle_expected : trace :=
  [Estep u_expected y_out; Epublish (tp_name base) (msg_x f_inf); Esleep 20].

Example t_expected: t = start_expected ++ cycle_expected.
Proof. vm_compute. reflexivity. Qed.

Lemma W : wf_facts landshark.
Proof. apply wf_facts_intro. vm_compute. reflexivity. Qed.

Theorem p_run_ok_concretely: run_ok landshark ctx 1 t.
Proof.
  exists (fun _ => tt), (fun _ => cycle_expected). split; [reflexivity|].
  split; [rewrite t_expected; reflexivity|].
  intros i Hi. assert (i = O) by (inversion Hi; [reflexivity|inversion H0]). subst i.
  exists u_expected, y_out, [msg_x f_inf]. split; [|split; [|split]].
  - reflexivity.
  - split; [apply mval_typecheck_iff; vm_compute; reflexivity|split; [|intros dr Hdr; destruct Hdr]].
    intros ir Hir. simpl in Hir.
    destruct Hir as [<-|[<-|[<-|[]]]].
    + exists left_wheel, (Vfloat f_zero). split; [simpl; auto|]. split; [reflexivity|]. split; vm_compute; reflexivity.
    + exists right_wheel, (Vfloat f_inf). split; [simpl; auto|]. split; [reflexivity|]. split; vm_compute; reflexivity.
    + exists gps, (Vfloat f_zero). split; [simpl; auto|]. split; [reflexivity|]. split; vm_compute; reflexivity.
  - reflexivity.
  - constructor; [|constructor]. split; [apply mval_typecheck_iff; vm_compute; reflexivity|split; [|split; [|split]]].
    + intros o Ho Eo. simpl in Ho. destruct Ho as [<-|[]].
      exists (Vfloat f_inf). split; vm_compute; reflexivity.
    + (* LandShark stamps nothing *)
      intros sp E. discriminate E.
    + (* nor has constant strings *)
      intros sp bs [].
    + intros lp q R NF _ _. apply (leaves_spec landshark _ lp q W) in R.
      vm_compute in R.
      destruct R as [R|[R|[R|[R|[R|[R|[R|[R|[R|[]]]]]]]]]]; inversion R; subst lp q;
        try (vm_compute; reflexivity).
      (* the fed leaf [twist.linear.x] is excluded *)
      exfalso. apply (NF (mkoutrel "Out1" "landshark_control_base_velocity" twist_x)); simpl; auto.
Qed.
