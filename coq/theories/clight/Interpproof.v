(** * Soundness of the interpreter (theorem T5) *)

(** Every result the interpreter of [Interp] returns is a result of the
    big-step semantics of [Semantics]: for statements, function calls, the
    deliveries of [ros_spinOnce], and whole programs.  The differential
    tests compare the interpreter with the compiled C; this theorem is
    what makes the interpreter's answers answers of the semantics. *)

From Coq Require Import String List ZArith Bool.
From ROSGen Require Import Syntax Values Memory Environment Semantics Interp.
Import ListNotations.

Section SOUNDNESS.

Context {CS : Type}.
Variable ctx : ros_context CS.
Variable ge : genv.

(** Take apart a hypothesis [match x with ... end = Some r]. *)
Local Ltac destr_some H :=
  repeat match type of H with
  | match ?x with _ => _ end = Some _ =>
      let E := fresh "E" in destruct x eqn:E; try discriminate H
  | Some _ = Some _ => inversion H; clear H; subst
  end.

Theorem interp_sound:
  forall fuel,
  (forall e le m w s t le' m' w' out,
     exec_stmt_fuel ctx ge fuel e le m w s = Some (t, le', m', w', out) ->
     exec_stmt ctx ge e le m w s t le' m' w' out)
  /\ (forall m w fd vargs t m' w' v,
     call_fuel ctx ge fuel m w fd vargs = Some (t, m', w', v) ->
     eval_funcall ctx ge m w fd vargs t m' w' v)
  /\ (forall m w msgs t m' w',
     deliver_fuel ctx ge fuel m w msgs = Some (t, m', w') ->
     deliver ctx ge m w msgs t m' w').
Proof.
  induction fuel as [|fuel IH].
  - split; [|split]; intros * H; discriminate H.
  - destruct IH as [IHs [IHc IHd]]. split; [|split].
    + (* statements *)
      intros e le m w s t le' m' w' out H. simpl in H.
      destruct s as [ | a1 a2 | x a | optid a al | s1 s2 | a s1 s2 | body | | [a|] ].
      * (* skip *) destr_some H. constructor.
      * (* a1 = a2 *) destr_some H. constructor; auto.
      * (* x = a *) destr_some H. constructor; auto.
      * (* call *)
        destruct (eval_expr ge e le m a) as [vf|] eqn:EV; try discriminate H.
        destruct vf as [| | | | | | fid]; try discriminate H.
        destruct (typeof a) as [| | | | | | targs tres |] eqn:TY; try discriminate H.
        destruct (find_funct ge fid) as [fd|] eqn:FD; try discriminate H.
        destruct (type_eq (type_of_fundef fd) (Tfunction targs tres)) as [TF|]; try discriminate H.
        destruct (eval_exprlist ge e le m al targs) as [vargs|] eqn:EL; try discriminate H.
        destruct (call_fuel ctx ge fuel m w fd vargs) as [[[[t1 m1] w1] vres]|] eqn:CF; try discriminate H.
        inversion H; subst. econstructor; eauto.
      * (* sequence *)
        destruct (exec_stmt_fuel ctx ge fuel e le m w s1) as [[[[[t1 le1] m1] w1] out1]|] eqn:E1;
          try discriminate H.
        destruct out1.
        -- destruct (exec_stmt_fuel ctx ge fuel e le1 m1 w1 s2) as [[[[[t2 le2] m2] w2] out2]|] eqn:E2;
             try discriminate H.
           inversion H; subst. eapply exec_Sseq_1; eauto.
        -- inversion H; subst. eapply exec_Sseq_2; eauto. discriminate.
        -- inversion H; subst. eapply exec_Sseq_2; eauto. discriminate.
      * (* if *)
        destruct (eval_expr ge e le m a) as [v|] eqn:EV; try discriminate H.
        destruct (bool_val v) as [b|] eqn:BV; try discriminate H.
        eapply exec_Sifthenelse; eauto.
      * (* loop *)
        destruct (exec_stmt_fuel ctx ge fuel e le m w body) as [[[[[t1 le1] m1] w1] out1]|] eqn:E1;
          try discriminate H.
        destruct out1 as [| | r].
        -- destruct (exec_stmt_fuel ctx ge fuel e le1 m1 w1 (Sloop body)) as [[[[[t2 le2] m2] w2] out2]|] eqn:E2;
             try discriminate H.
           inversion H; subst. eapply exec_Sloop_loop; eauto.
        -- inversion H; subst. apply (exec_Sloop_stop ctx ge e le m w body t le' m' w' Out_break); auto.
           discriminate.
        -- inversion H; subst. apply (exec_Sloop_stop ctx ge e le m w body t le' m' w' (Out_return r)); auto.
           discriminate.
      * (* break *) destr_some H. constructor.
      * (* return a *) destr_some H. constructor; auto.
      * (* return *) destr_some H. constructor.
    + (* calls *)
      intros m w fd vargs t m' w' v H. simpl in H.
      destruct fd as [f | ef targs tres].
      * destruct (function_entry (ge_comp ge) f vargs m) as [[[e le] m1]|] eqn:FE; try discriminate H.
        destruct (exec_stmt_fuel ctx ge fuel e le m1 w (fn_body f)) as [[[[[t1 le1] m2] w1] out]|] eqn:EX;
          try discriminate H.
        destruct (outcome_result (fn_return f) out) as [vres|] eqn:OR; try discriminate H.
        inversion H; subst. econstructor; eauto.
      * destruct ef;
          try (destruct (external_call ctx ge _ vargs m w) as [[[[vres t1] m1] w1]|] eqn:EC;
               [inversion H; subst; apply eval_funcall_external; auto | discriminate H]).
        (* ros_spinOnce *)
        destruct vargs; try discriminate H.
        destruct (deliver_fuel ctx ge fuel m w (spin_messages ctx w)) as [[[t1 m1] w1]|] eqn:DF;
          try discriminate H.
        inversion H; subst. apply eval_funcall_spinOnce; auto.
    + (* deliveries *)
      intros m w msgs t m' w' H. simpl in H.
      destruct msgs as [|[s mv] rest].
      * inversion H; subst; constructor.
      * destruct (accepted ge s mv) eqn:Acc; simpl in H; [|apply deliver_rejected; auto].
        destruct (alloc m (Tstruct (sub_msgty s)) (delivered ge s mv)) as [m1 b] eqn:AL.
        assert (AL': alloc m (Tstruct (sub_msgty s)) (delivered ge s mv) = (m1, b)) by exact AL.
        unfold alloc in AL'. inversion AL'; subst m1 b; clear AL'.
        destruct (find_funct ge (sub_callback s)) as [fd|] eqn:FD; try discriminate H.
        match type of H with
        | context [call_fuel ?c ?g ?f ?m1 ?w1 ?fd1 ?args] =>
            destruct (call_fuel c g f m1 w1 fd1 args) as [[[[t1 m2] w1'] v]|] eqn:CF;
              try discriminate H
        end.
        match type of H with
        | context [deliver_fuel ?c ?g ?f ?m2 ?w2 ?msgs] =>
            destruct (deliver_fuel c g f m2 w2 msgs) as [[[t2 m3] w2']|] eqn:DF;
              try discriminate H
        end.
        inversion H; subst. econstructor; eauto.
Qed.

Lemma exec_stmt_fuel_sound:
  forall fuel e le m w s t le' m' w' out,
  exec_stmt_fuel ctx ge fuel e le m w s = Some (t, le', m', w', out) ->
  exec_stmt ctx ge e le m w s t le' m' w' out.
Proof. intros fuel; apply (interp_sound fuel). Qed.

Lemma call_fuel_sound:
  forall fuel m w fd vargs t m' w' v,
  call_fuel ctx ge fuel m w fd vargs = Some (t, m', w', v) ->
  eval_funcall ctx ge m w fd vargs t m' w' v.
Proof. intros fuel; apply (interp_sound fuel). Qed.

Lemma deliver_fuel_sound:
  forall fuel m w msgs t m' w',
  deliver_fuel ctx ge fuel m w msgs = Some (t, m', w') ->
  deliver ctx ge m w msgs t m' w'.
Proof. intros fuel; apply (interp_sound fuel). Qed.

End SOUNDNESS.

(** T5: a trace computed by running a whole program is a behaviour of the
    program. *)
Theorem run_program_sound:
  forall (CS : Type) (ctx : ros_context CS) fuel p n t v m' w',
  run_program fuel p ctx n = Some (t, v, m', w') ->
  program_behaves p ctx n t.
Proof.
  intros CS ctx fuel p n t v m' w' H. unfold run_program in H.
  destruct (find_funct (globalenv p) (prog_main p)) as [fd|] eqn:FD; try discriminate H.
  destruct (call_fuel ctx (globalenv p) fuel (init_mem p) (initial_world ctx n) fd [])
    as [[[[t1 m1] w1] v1]|] eqn:CF; try discriminate H.
  inversion H; subst. econstructor; eauto. eapply call_fuel_sound; eauto.
Qed.

Theorem run_trace_sound:
  forall (CS : Type) (ctx : ros_context CS) fuel p n t,
  run_trace fuel p ctx n = Some t -> program_behaves p ctx n t.
Proof.
  intros CS ctx fuel p n t H. unfold run_trace in H.
  destruct (run_program fuel p ctx n) as [[[[t1 v] m'] w']|] eqn:R; try discriminate H.
  inversion H; subst. eapply run_program_sound; eauto.
Qed.

(** With determinism: the trace the interpreter computes is the only
    behaviour of the program. *)
Theorem run_trace_exact:
  forall (CS : Type) (ctx : ros_context CS) fuel p n t t',
  run_trace fuel p ctx n = Some t -> program_behaves p ctx n t' -> t' = t.
Proof.
  intros CS ctx fuel p n t t' R B.
  apply (program_behaves_determ CS p ctx n); auto. eapply run_trace_sound; eauto.
Qed.
