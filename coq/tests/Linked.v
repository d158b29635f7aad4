(** * The linked program (T8): a run, and mutants of the controller's C *)

(** A relay node: it subscribes to [/in] ([geometry_msgs/Twist], queue 1)
    and publishes on [/out] its controller's output as [linear.x].  The
    controller is a block diagram with one state: [y] is the previous
    input, [0.5] at first (a UnitDelay).  Three cycles with inputs [1.0]
    and [2.0] (and none in the third): the linked program, glue and
    generated controller in one semantics, publishes [0.5], [1.0] and
    [2.0], which the interpreter computes ([linked_run]), with no
    controller event in its trace; T8 applies ([relay_linked]).

    Mutants of the controller's C, each run linked with the same glue and
    refuted against T8's statement for that program ([t8_for]): an
    initialisation that leaves the state at zero (k1), a step that stores
    the next state before writing the outputs (k2), and a link that leaves
    the environment's [Controller_initialize] in place of the generated
    one (k3: it emits [Einit], and the state in memory stays at zero, not
    at the diagram's [0.5]). *)

From Coq Require Import String List ZArith Lia.
From Flocq Require Import IEEE754.Binary IEEE754.Bits.
From ROSGen Require Import FloatBits Errors Syntax Values Memory Environment Semantics Interp Interpproof
  NodeModel Wellformed Generator Generatorspec DDC Loopproof Diagram Diagramgen Endtoend Link.
From ROSGenTests Require Import LandShark.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope list_scope.

Definition f64 (bits : Z) : val := Vfloat (float64_of_bits bits).
Definition half : Z := 0x3FE0000000000000.
Definition one : Z := 0x3FF0000000000000.
Definition two : Z := 0x4000000000000000.

Definition lin_x : path := [PField "linear"; PField "x"].

Definition tin : topic := mktopic "/in" "in" "geometry_msgs/Twist" Subscribe "geometry_msgs_Twist" 1.
Definition tout : topic := mktopic "/out" "out" "geometry_msgs/Twist" Publish "geometry_msgs_Twist" 1.

Definition relay : node_model := {|
  nm_name := "relay"; nm_period_ms := 10; nm_ctrl := "Controller";
  nm_in_var := "Controller_U"; nm_in_struct := "ExtU_Controller_T";
  nm_inputs := [("x", FTprim Pfloat64)];
  nm_out_var := "Controller_Y"; nm_out_struct := "ExtY_Controller_T";
  nm_outputs := [("y", FTprim Pfloat64)];
  nm_msgs := [geometry_msgs_Vector3; geometry_msgs_Twist];
  nm_topics := [tin; tout];
  nm_inrels := [mkinrel "in" lin_x "x"];
  nm_outrels := [mkoutrel "y" "out" lin_x];
  nm_timeouts := []; nm_fallbacks := []; nm_drels := []; nm_stamps := []; nm_stamp_from := [];
  nm_strings := [] |}.

Definition delay : diagram := mkdiagram "Controller"
  "Controller_U" "ExtU_Controller_T" [("x", Pfloat64)]
  "Controller_Y" "ExtY_Controller_T" [("y", Pfloat64)]
  "Controller_DW" "DW_Controller_T" [mkstate "z" Pfloat64 (f64 half) "x" Kdelay]
  [mkeq "x" Pfloat64 (Binport "x"); mkeq "z" Pfloat64 (Bstate "z")]
  [("y", "z")].

Example delay_wf : dg_wf delay = true.
Proof. vm_compute. reflexivity. Qed.

Example delay_matches : dg_matches relay delay = true.
Proof. vm_compute. reflexivity. Qed.

Example relay_fresh : link_fresh relay delay = true.
Proof. vm_compute. reflexivity. Qed.

Definition relay_result : res program := Eval vm_compute in generate relay.
Definition relay_prog : program :=
  Eval vm_compute in match relay_result with OK p => p | Error _ => mkprogram [] [] "" end.

Lemma relay_generate : generate relay = OK relay_prog.
Proof. vm_compute. reflexivity. Qed.

(** T8 for this node. *)
Theorem relay_linked : linked_node_ok relay relay_prog delay.
Proof. exact (linked_node_ddc relay relay_prog delay relay_generate delay_wf delay_matches relay_fresh). Qed.

(** ** A run *)

Definition twist (x : Z) : mval :=
  MVstruct [("linear", MVstruct [("x", MVscalar (f64 x)); ("y", MVscalar (f64 0)); ("z", MVscalar (f64 0))]);
            ("angular", MVstruct [("x", MVscalar (f64 0)); ("y", MVscalar (f64 0)); ("z", MVscalar (f64 0))])].

Definition arrivals (k : nat) : list arrival :=
  match k with
  | O => [mkarrival "/in" (twist one) 5]
  | 1%nat => [mkarrival "/in" (twist two) 15]
  | _ => []
  end.
Definition clock (k : nat) : Z := Z.of_nat k * 10.

(** Any environment: its controller is never called by the linked program. *)
Definition ctxL : ros_context unit := mkctx arrivals clock tt (fun s u => (s, u)) Ros1.

Definition expected : trace :=
  [Esubscribe "/in" "geometry_msgs_Twist" 1; Eadvertise "/out" "geometry_msgs_Twist" 1;
   Epublish "/out" (twist half); Esleep 10;
   Epublish "/out" (twist one); Esleep 10;
   Epublish "/out" (twist two); Esleep 10].

Definition fuel : nat := Eval vm_compute in (100 * 100)%nat.

Example linked_run : run_trace fuel (link relay_prog delay) ctxL 3 = Some expected.
Proof. vm_compute. reflexivity. Qed.

(** ** Mutants *)

(** T8's statement for a program [q] in place of [link relay_prog delay]. *)
Definition t8_for (q : program) : Prop :=
  forall t, program_behaves q ctxL 3 t ->
  exists (s : nat -> mval) (evs : nat -> trace),
     s O = dg_init delay
  /\ t = linked_start_events relay ++ concat (map evs (seq 0 3))
  /\ forall i, (i < 3)%nat ->
       exists u y mvs,
          evs i = publish_events relay (published relay) mvs ++ [Esleep (nm_period_ms relay)]
       /\ input_values relay (diagram_ctx relay delay arrivals clock Ros1) i u
       /\ dg_step delay (s i) u = (s (S i), y)
       /\ Forall2 (published_value relay y (clock (S i)) (newest_by relay (diagram_ctx relay delay arrivals clock Ros1) i))
                  (published relay) mvs.

Lemma t8_linked : t8_for (link relay_prog delay).
Proof.
  intros t B. destruct (relay_linked arrivals clock Ros1 3 unit ctxL eq_refl eq_refl eq_refl) as [_ H].
  - intros k a tp Ha Htp E. destruct k as [|[|k]]; simpl in Ha; try contradiction;
      destruct Ha as [<-|[]]; simpl in Htp; destruct Htp as [<-|[]]; vm_compute; repeat econstructor.
  - exact (H t B).
Qed.

(** The published message as the glue sends it: [linear.x] as written. *)
Lemma sent_twist_x:
  forall mv x, mval_has_type (composites relay) (Tstruct "geometry_msgs_Twist") mv ->
  mval_get mv (path_steps lin_x) = Some (MVscalar x) ->
  mval_get (sent relay tout mv) (path_steps lin_x) = Some (MVscalar x).
Proof. intros mv x T G. eapply sent_scalar; eauto; reflexivity. Qed.

(** A program satisfying T8's statement publishes [0.5] first: the
    diagram's output in its initial state, whatever the input. *)
Lemma t8_first:
  forall q t, t8_for q -> program_behaves q ctxL 3 t ->
  exists mv, nth_error t 2 = Some (Epublish "/out" mv)
          /\ mval_get mv (path_steps lin_x) = Some (MVscalar (f64 half)).
Proof.
  intros q t T B. destruct (T t B) as (s & evs & S0 & Et & C).
  destruct (C 0%nat ltac:(lia)) as (u & y & mvs & E0 & _ & ST & PV).
  rewrite S0 in ST. simpl in PV. inversion PV as [|tp mv tps mvs' P Pn]; subst. inversion Pn; subst.
  exists (sent relay tout mv). split.
  - simpl. rewrite E0. reflexivity.
  - destruct P as (Tm & O & _). destruct (O (mkoutrel "y" "out" lin_x) (or_introl eq_refl) eq_refl) as (v & Gy & Gm).
    assert (Y: y = snd (dg_step delay (dg_init delay) u)) by (rewrite ST; reflexivity).
    rewrite Y in Gy. simpl in Gy. inversion Gy; subst. apply sent_twist_x; auto.
Qed.

(** A program whose run publishes another [linear.x] first does not
    satisfy T8's statement. *)
Lemma refute:
  forall q t mv x, run_trace fuel q ctxL 3 = Some t -> nth_error t 2 = Some (Epublish "/out" mv) ->
  mval_get mv (path_steps lin_x) = Some (MVscalar x) -> x <> f64 half -> ~ t8_for q.
Proof.
  intros q t mv x R E G N T. destruct (t8_first q t T (run_trace_sound _ _ _ _ _ _ R)) as (mv' & E' & G').
  rewrite E in E'. inversion E'; subst. rewrite G in G'. inversion G'. auto.
Qed.

Lemma zero_not_half : f64 0 <> f64 half.
Proof. vm_compute. discriminate. Qed.

(** The program [link relay_prog delay] with [init] and [step] for the
    generated [Controller_initialize] and [Controller_step]. *)
Definition link_with (init step : function) : program :=
  let lfd fd := match fd with
                | External (EF_controller_initialize _ _) _ _ => Internal init
                | External (EF_controller_step _ _) _ _ => Internal step
                | _ => fd
                end in
  mkprogram (prog_types relay_prog ++ state_types delay)
            (state_defs delay ++ map (ldef lfd) (prog_defs relay_prog)) (prog_main relay_prog).

Example link_with_generated : link_with (init_function delay) (step_function delay) = link relay_prog delay.
Proof. reflexivity. Qed.

(** (k1) [Controller_initialize] that leaves the state at zero. *)
Definition k1_init : function := mkfunction Tvoid [] [] [] Sskip.

Theorem k1_refuted : ~ t8_for (link_with k1_init (step_function delay)).
Proof.
  eapply refute with (x := f64 0); [vm_compute; reflexivity | reflexivity | reflexivity | apply zero_not_half].
Qed.

(** (k2) [Controller_step] that stores the next state before writing
    the outputs: the output is already the next state (the first
    publication is [1.0]). *)
Definition k2_step : function :=
  let f := step_function delay in mkfunction (fn_return f) (fn_params f) (fn_vars f) (fn_temps f)
    (Ssequence (seq_list (map (eq_stmt delay) (dg_eqs delay)))
       (Ssequence (seq_list (map (update_stmt delay) (dg_states delay)))
                  (seq_list (map (eq_stmt delay) [mkeq "z" Pfloat64 (Bstate "z")]
                             ++ map (out_stmt delay) (dg_outputs delay))))).

Theorem k2_refuted : ~ t8_for (link_with (init_function delay) k2_step).
Proof.
  eapply refute with (x := f64 one); [vm_compute; reflexivity | reflexivity | reflexivity |].
  vm_compute. discriminate.
Qed.

(** (k3) The environment's [Controller_initialize] left in place of the
    generated one: the linked program emits [Einit], and its state stays
    at zero. *)
Definition k3 : program :=
  let lfd fd := match fd with
                | External (EF_controller_step _ _) _ _ => Internal (step_function delay)
                | _ => fd
                end in
  mkprogram (prog_types relay_prog ++ state_types delay)
            (state_defs delay ++ map (ldef lfd) (prog_defs relay_prog)) (prog_main relay_prog).

Lemma t8_starts:
  forall q t, t8_for q -> program_behaves q ctxL 3 t ->
  nth_error t 0 = Some (Esubscribe "/in" "geometry_msgs_Twist" 1).
Proof. intros q t T B. destruct (T t B) as (s & evs & _ & -> & _). reflexivity. Qed.

Theorem k3_refuted : ~ t8_for k3.
Proof.
  intros T. destruct (run_trace fuel k3 ctxL 3) as [t|] eqn:R.
  - assert (S := t8_starts k3 t T (run_trace_sound _ _ _ _ _ _ R)). vm_compute in R. inversion R; subst.
    discriminate S.
  - vm_compute in R. discriminate R.
Qed.
