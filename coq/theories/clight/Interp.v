(** * An executable interpreter for the semantics *)

(** Fuel-based functions that compute what the big-step judgements of
    [Semantics] relate: [exec_stmt_fuel] for statements, [call_fuel] for
    function calls, [deliver_fuel] for the callbacks of one
    [ros_spinOnce], and [run_program] for whole programs.  Every nested
    statement, loop iteration, call and delivered message consumes one
    unit of fuel; [None] means "out of fuel or undefined behaviour".
    They run under [vm_compute] (see [tests/InterpExamples.v]), and
    [Interpproof] proves that whatever they return is a result of the
    semantics (theorem T5). *)

From Coq Require Import String List ZArith Bool.
From ROSGen Require Import Syntax Values Memory Environment Semantics.
Import ListNotations.

Section INTERP.

Context {CS : Type}.
Variable ctx : ros_context CS.
Variable ge : genv.

Fixpoint exec_stmt_fuel (fuel : nat) (e : env) (le : temp_env) (m : mem) (w : world CS)
                        (s : statement) {struct fuel}
  : option (trace * temp_env * mem * world CS * outcome) :=
  match fuel with
  | O => None
  | S fuel' =>
      match s with
      | Sskip => Some ([], le, m, w, Out_normal)
      | Sassign a1 a2 =>
          match eval_assign ge e le m a1 a2 with
          | Some m' => Some ([], le, m', w, Out_normal)
          | None => None
          end
      | Sset x a =>
          match eval_expr ge e le m a with
          | Some v => Some ([], set_assoc x v le, m, w, Out_normal)
          | None => None
          end
      | Scall optid a al =>
          match eval_expr ge e le m a, typeof a with
          | Some (Vfptr fid), Tfunction targs tres =>
              match find_funct ge fid with
              | Some fd =>
                  if type_eq (type_of_fundef fd) (Tfunction targs tres) then
                    match eval_exprlist ge e le m al targs with
                    | Some vargs =>
                        match call_fuel fuel' m w fd vargs with
                        | Some (t, m', w', vres) =>
                            Some (t, set_opttemp optid vres le, m', w', Out_normal)
                        | None => None
                        end
                    | None => None
                    end
                  else None
              | None => None
              end
          | _, _ => None
          end
      | Ssequence s1 s2 =>
          match exec_stmt_fuel fuel' e le m w s1 with
          | Some (t1, le1, m1, w1, Out_normal) =>
              match exec_stmt_fuel fuel' e le1 m1 w1 s2 with
              | Some (t2, le2, m2, w2, out) => Some (t1 ++ t2, le2, m2, w2, out)
              | None => None
              end
          | Some r => Some r
          | None => None
          end
      | Sifthenelse a s1 s2 =>
          match eval_expr ge e le m a with
          | Some v =>
              match bool_val v with
              | Some b => exec_stmt_fuel fuel' e le m w (if b then s1 else s2)
              | None => None
              end
          | None => None
          end
      | Sloop body =>
          match exec_stmt_fuel fuel' e le m w body with
          | Some (t1, le1, m1, w1, Out_normal) =>
              match exec_stmt_fuel fuel' e le1 m1 w1 (Sloop body) with
              | Some (t2, le2, m2, w2, out) => Some (t1 ++ t2, le2, m2, w2, out)
              | None => None
              end
          | Some (t1, le1, m1, w1, out) => Some (t1, le1, m1, w1, loop_outcome out)
          | None => None
          end
      | Sbreak => Some ([], le, m, w, Out_break)
      | Sreturn None => Some ([], le, m, w, Out_return None)
      | Sreturn (Some a) =>
          match eval_expr ge e le m a with
          | Some v => Some ([], le, m, w, Out_return (Some v))
          | None => None
          end
      end
  end

with call_fuel (fuel : nat) (m : mem) (w : world CS) (fd : fundef) (vargs : list val)
               {struct fuel}
  : option (trace * mem * world CS * val) :=
  match fuel with
  | O => None
  | S fuel' =>
      match fd with
      | Internal f =>
          match function_entry (ge_comp ge) f vargs m with
          | Some (e, le, m1) =>
              match exec_stmt_fuel fuel' e le m1 w (fn_body f) with
              | Some (t, le', m2, w', out) =>
                  match outcome_result (fn_return f) out with
                  | Some vres => Some (t, free_vars m2 e, w', vres)
                  | None => None
                  end
              | None => None
              end
          | None => None
          end
      | External EF_ros_spinOnce _ _ =>
          match vargs with
          | [] =>
              match deliver_fuel fuel' m w (spin_messages ctx w) with
              | Some (t, m', w') => Some (t, m', next_spin ctx w', Vundef)
              | None => None
              end
          | _ => None
          end
      | External ef _ _ =>
          match external_call ctx ge ef vargs m w with
          | Some (vres, t, m', w') => Some (t, m', w', vres)
          | None => None
          end
      end
  end

with deliver_fuel (fuel : nat) (m : mem) (w : world CS) (msgs : list (subscription * arrival))
                  {struct fuel}
  : option (trace * mem * world CS) :=
  match fuel with
  | O => None
  | S fuel' =>
      match msgs with
      | [] => Some ([], m, w)
      | (s, a) :: rest =>
          if negb (accepted ge s a) then deliver_fuel fuel' m w rest else
          let (m1, b) := alloc m (Tstruct (sub_msgty s)) (delivered ge s a) in
          match find_funct ge (sub_callback s) with
          | Some fd =>
              match call_fuel fuel' m1 (set_time w (ar_time a)) fd [Vptr b []] with
              | Some (t1, m2, w1, _) =>
                  match deliver_fuel fuel' (free m2 b) w1 rest with
                  | Some (t2, m3, w2) => Some (t1 ++ t2, m3, w2)
                  | None => None
                  end
              | None => None
              end
          | None => None
          end
      end
  end.

End INTERP.

(** Run [main] of [p] in the environment [ctx] where [ros_ok] answers
    true [n] times: the events, [main]'s result, the final memory and
    world. *)
Definition run_program {CS : Type} (fuel : nat) (p : program) (ctx : ros_context CS) (n : nat)
  : option (trace * val * mem * world CS) :=
  match find_funct (globalenv p) (prog_main p) with
  | Some fd =>
      match call_fuel ctx (globalenv p) fuel (init_mem p) (initial_world ctx n) fd [] with
      | Some (t, m', w', v) => Some (t, v, m', w')
      | None => None
      end
  | None => None
  end.

(** Just the events of a run. *)
Definition run_trace {CS : Type} (fuel : nat) (p : program) (ctx : ros_context CS) (n : nat)
  : option trace :=
  match run_program fuel p ctx n with
  | Some (t, _, _, _) => Some t
  | None => None
  end.
