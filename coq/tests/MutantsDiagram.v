(** * The mutation catalogue of the controller generator *)

(** T6 ([Diagramproof.step_call], [Main.controller_step_correct]) says
    that [Controller_step] ends with [Controller_Y] holding the outputs of
    [Diagram.dg_step].  Each mutant below is a plausible bug of
    [Diagramgen.eq_stmt] (the statement of one block); for each, on a small
    well-formed diagram and one concrete memory, the mutant's run is
    computed by the interpreter (T5 makes it a run of the semantics, the
    only one by determinism), and its outputs differ from [dg_step]'s: so
    no generator with that bug could have proved T6.  The unmutated
    generator's run gives [dg_step]'s outputs ([generated_passes]).

    The diagram: inputs [a], [b] ([double]), output [y];
    [y = sat(min(a, b) - (a - b), -1, 1)] computed as
    [lo = min a b; d = a - b; s = lo - d; y = saturation -1 1 s].
    Each mutant is run on inputs that expose it: [a = +0.0, b = -0.0]
    ([<] and [<=] differ on [min]), [a = 3.0, b = 0.5] (the signs of a
    sum), [a = 0.25, b = 0.5] (the bounds of the saturation, the order of
    a sum's terms). *)

From Coq Require Import String List ZArith Bool.
From Flocq Require Import IEEE754.Binary IEEE754.Bits.
From ROSGen Require Import Syntax Values Memory Environment Semantics Interp Interpproof.
From ROSGen Require Import FloatBits NodeModel Diagram Diagramgen.
Import ListNotations.
Local Open Scope string_scope.

Definition f64 (bits : Z) : val := Vfloat (float64_of_bits bits).

Definition d0 : diagram := mkdiagram "Controller"
  "Controller_U" "ExtU_Controller_T" [("a", Pfloat64); ("b", Pfloat64)]
  "Controller_Y" "ExtY_Controller_T" [("y", Pfloat64)]
  "Controller_DW" "DW_Controller_T" []
  [mkeq "a" Pfloat64 (Binport "a");
   mkeq "b" Pfloat64 (Binport "b");
   mkeq "lo" Pfloat64 (Bminmax false ["a"; "b"]);
   mkeq "d" Pfloat64 (Bsum [(true, "a"); (false, "b")]);
   mkeq "s" Pfloat64 (Bsum [(true, "lo"); (false, "d")]);
   mkeq "y" Pfloat64 (Bsaturation (f64 0xBFF0000000000000) (f64 0x3FF0000000000000) "s")]
  [("y", "y")].

Example d0_wf : dg_wf d0 = true.
Proof. vm_compute. reflexivity. Qed.

(** ** Mutants of [eq_stmt] *)

(** A program whose [Controller_step] is built with [stmt] for each
    equation instead of [eq_stmt d]. *)
Definition step_with (stmt : equation -> statement) (d : diagram) : function :=
  mkfunction Tvoid [] [] (map (fun e => (temp_of (eq_sig e), ct (eq_type e))) (dg_eqs d))
    (Ssequence (seq_list (map stmt (dg_eqs d)))
       (Ssequence (seq_list (map (out_stmt d) (dg_outputs d)))
                  (seq_list (map (update_stmt d) (dg_states d))))).

(** The same function as [Diagramgen.step_function]. *)
Example step_with_eq : step_with (eq_stmt d0) d0 = step_function d0.
Proof. reflexivity. Qed.

Definition program_with (f : function) (d : diagram) : program :=
  mkprogram (prog_types (dg_program d))
    [(dg_in_var d, Gvar (Tstruct (dg_in_struct d))); (dg_out_var d, Gvar (Tstruct (dg_out_struct d)));
     (step_name d, Gfun (Internal f))]
    (step_name d).

(** (m1) MinMax compares with [<=] instead of [<]: on [min(+0, -0)] it
    takes [-0]. *)
Definition m_minmax_le (e : equation) : statement :=
  match eq_block e with
  | Bminmax false (a :: [b]) =>
      let x := temp_of (eq_sig e) in
      Ssequence (Sset x (tmp a Pfloat64))
        (Sifthenelse (Ebinop Ole (tmp b Pfloat64) (Etempvar x tdouble) tint)
                     (Sset x (tmp b Pfloat64)) Sskip)
  | _ => eq_stmt d0 e
  end.

(** (m2) Sum drops the signs: [a + b] for [a - b]. *)
Definition m_sum_signs (e : equation) : statement :=
  match eq_block e with
  | Bsum terms => eq_stmt d0 (mkeq (eq_sig e) (eq_type e) (Bsum (map (fun t => (true, snd t)) terms)))
  | _ => eq_stmt d0 e
  end.

(** (m3) Saturation with its bounds swapped. *)
Definition m_sat_swap (e : equation) : statement :=
  match eq_block e with
  | Bsaturation lo hi a => eq_stmt d0 (mkeq (eq_sig e) (eq_type e) (Bsaturation hi lo a))
  | _ => eq_stmt d0 e
  end.

(** (m4) The operands of a two-input Sum taken in the other order:
    [b - a] for [a - b]. *)
Definition m_sum_order (e : equation) : statement :=
  match eq_block e with
  | Bsum [t1; t2] => eq_stmt d0 (mkeq (eq_sig e) (eq_type e) (Bsum [(fst t1, snd t2); (fst t2, snd t1)]))
  | _ => eq_stmt d0 e
  end.

(** ** Runs *)

Definition quiet : ros_context unit := mkctx (fun _ => []) (fun _ => 0%Z) tt (fun s u => (s, u)) Ros1.
Definition w0 : world unit := initial_world quiet 0.

Definition inputs (a b : Z) : mval := MVstruct [("a", MVscalar (f64 a)); ("b", MVscalar (f64 b))].

(** The memory of [program_with f d0] with the inputs [a], [b] stored in
    [Controller_U]. *)
Definition mem_with (f : function) (a b : Z) : option mem :=
  let p := program_with f d0 in
  match find_var (globalenv p) "Controller_U" with
  | Some (bu, _) => store_path (init_mem p) bu [] (inputs a b)
  | None => None
  end.

(** The value of [Controller_Y.y] after a run, as bits, if the run ends. *)
Definition y_after (f : function) (a b : Z) : option Z :=
  let p := program_with f d0 in
  match mem_with f a b, find_var (globalenv p) "Controller_Y" with
  | Some m, Some (by_, _) =>
      match call_fuel quiet (globalenv p) 100 m w0 (Internal f) [] with
      | Some (_, m', _, _) =>
          match load_path m' by_ [Sfield "y"] with
          | Some (MVscalar (Vfloat x)) => Some (bits_of_b64 x)
          | _ => None
          end
      | None => None
      end
  | _, _ => None
  end.

(** What [dg_step] gives, as bits. *)
Definition y_spec (a b : Z) : option Z :=
  match mval_get (snd (dg_step d0 (MVstruct []) (inputs a b))) [Sfield "y"] with
  | Some (MVscalar (Vfloat x)) => Some (bits_of_b64 x)
  | _ => None
  end.

(** The generated step gives [dg_step]'s output on both memories. *)
Example generated_passes:
  y_after (step_function d0) 0x0 0x8000000000000000 = y_spec 0x0 0x8000000000000000
  /\ y_after (step_function d0) 0x4008000000000000 0x3FE0000000000000
     = y_spec 0x4008000000000000 0x3FE0000000000000
  /\ y_after (step_function d0) 0x3FD0000000000000 0x3FE0000000000000
     = y_spec 0x3FD0000000000000 0x3FE0000000000000.
Proof. vm_compute. repeat split; reflexivity. Qed.

(** ** Each mutant is refuted *)

(** What T6 says of a step function [f] on the memory with inputs [a],
    [b]: its run ends with [Controller_Y] holding [dg_step]'s outputs. *)
Definition t6_holds (f : function) (a b : Z) : Prop :=
  let p := program_with f d0 in
  forall m bY tyY, mem_with f a b = Some m ->
  find_var (globalenv p) "Controller_Y" = Some (bY, tyY) ->
  exists m' tY, eval_funcall quiet (globalenv p) m w0 (Internal f) [] [] m' w0 Vundef
             /\ get_block m' bY = Some (tY, snd (dg_step d0 (MVstruct []) (inputs a b))).

(** The refutation: the interpreter's run is the run (T5 and
    determinism), and its output is not [dg_step]'s. *)
Lemma refute:
  forall f a b m bY tyY t m' w' v,
  let p := program_with f d0 in
  mem_with f a b = Some m ->
  find_var (globalenv p) "Controller_Y" = Some (bY, tyY) ->
  call_fuel quiet (globalenv p) 100 m w0 (Internal f) [] = Some (t, m', w', v) ->
  (forall tY, get_block m' bY = Some (tY, snd (dg_step d0 (MVstruct []) (inputs a b))) -> False) ->
  ~ t6_holds f a b.
Proof.
  intros f a b m bY tyY t m' w' v p M Y C NE H.
  destruct (H m bY tyY M Y) as [m'' [tY [E G]]].
  apply call_fuel_sound in C.
  destruct (semantics_determ quiet (globalenv p)) as [_ [D _]].
  destruct (D _ _ _ _ _ _ _ _ C _ _ _ _ E) as [_ [Em _]]. subst m''.
  exact (NE tY G).
Qed.

(** The bits of [y] in a block's value. *)
Definition y_bits (o : option (type * mval)) : Z :=
  match o with
  | Some (_, mv) => match mval_get mv [Sfield "y"] with
                    | Some (MVscalar (Vfloat x)) => bits_of_b64 x
                    | _ => -1
                    end
  | None => -1
  end%Z.

Ltac refute_mutant :=
  eapply refute; [vm_compute; reflexivity | vm_compute; reflexivity | vm_compute; reflexivity |];
  intros tY G; apply (f_equal y_bits) in G; vm_compute in G; discriminate G.

Theorem minmax_le_refuted: ~ t6_holds (step_with m_minmax_le d0) 0x0 0x8000000000000000.
Proof. refute_mutant. Qed.

Theorem sum_signs_refuted: ~ t6_holds (step_with m_sum_signs d0) 0x4008000000000000 0x3FE0000000000000.
Proof. refute_mutant. Qed.

Theorem sat_swap_refuted:
  ~ t6_holds (step_with m_sat_swap d0) 0x3FD0000000000000 0x3FE0000000000000.
Proof. refute_mutant. Qed.

Theorem sum_order_refuted:
  ~ t6_holds (step_with m_sum_order d0) 0x3FD0000000000000 0x3FE0000000000000.
Proof. refute_mutant. Qed.
