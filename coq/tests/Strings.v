(** * Constant strings (rule 4.14): the generator, the interpreter, and mutants *)

(** The LandShark node whose [std_msgs/Header] carries [frame_id] as a
    string of at most 16 bytes ([ros_string16]) and whose published
    command has [header.frame_id = "base_link"]: [generate] accepts it and
    refuses bad constant strings naming the culprit; the interpreter runs
    it, and every published message holds the constant exactly (length
    9, the 9 bytes, zero after them and in [truncated]); five mutants of
    the string code are refuted against T2: the length off by one, a
    wrong byte, the last byte left out, a byte written past the length
    (no zero padding), the strings written before the zeroing. *)

From Coq Require Import String List ZArith Lia.
From Flocq Require Import IEEE754.Binary IEEE754.Bits.
From ROSGen Require Import FloatBits Errors Syntax Values Memory Environment Semantics Interp Interpproof
  NodeModel Wellformed Generator Generatorspec DDC Loopproof.
From ROSGenTests Require Import LandShark.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope list_scope.

(** ** The model *)

Definition ros_string16 : msgdef :=
  mkmsgdef "ros_string16" [("len", FTprim Puint32); ("truncated", FTprim Pbool);
                           ("data", FTarray (FTprim Puint8) 16)].
Definition header_framed : msgdef :=
  mkmsgdef "std_msgs_Header" [("seq", FTprim Puint32); ("stamp", FTmsg "ros_time");
                              ("frame_id", FTmsg "ros_string16")].

Definition framed_msgs : list msgdef :=
  [ros_time; ros_string16; header_framed; geometry_msgs_Vector3; geometry_msgs_Twist;
   geometry_msgs_TwistStamped].

Definition frame_id : path := [PField "header"; PField "frame_id"].

(** "base_link" *)
Definition base_link : list Z := [98; 97; 115; 101; 95; 108; 105; 110; 107]%Z.

Definition with_strings (l : list (ident * (path * list Z))) : node_model :=
  reshape landshark (nm_inputs landshark) framed_msgs [] [] [] [] [] l.

Definition framed : node_model :=
  with_strings [("landshark_control_base_velocity", (frame_id, base_link))].

(** ** The generator *)

Example framed_wf: wf framed = true.
Proof. vm_compute. reflexivity. Qed.

Definition framed_result : res program := Eval vm_compute in generate framed.
Definition framed_prog : program :=
  Eval vm_compute in match framed_result with OK p => p | Error _ => mkprogram [] [] "" end.

Lemma framed_generates: generate framed = OK framed_prog.
Proof. vm_compute. reflexivity. Qed.

(** The empty string and a string of exactly 16 bytes are accepted. *)
Example empty_ok: wf (with_strings [("landshark_control_base_velocity", (frame_id, []))]) = true.
Proof. vm_compute. reflexivity. Qed.

Example full_ok:
  wf (with_strings [("landshark_control_base_velocity", (frame_id, repeat 120%Z 16))]) = true.
Proof. vm_compute. reflexivity. Qed.

Definition bad_string (what : string) : string :=
  "Generator: bad constant string (rule 4.14) on topic " ++ what
  ++ " must be a string field of a published message, long enough, that no output relation writes, and the constant bytes".

Example refuse_too_long:
  refused (with_strings [("landshark_control_base_velocity", (frame_id, repeat 120%Z 17))])
    (bad_string "'landshark_control_base_velocity': '.header.frame_id'").
Proof. vm_compute. reflexivity. Qed.

Example refuse_not_byte:
  refused (with_strings [("landshark_control_base_velocity", (frame_id, [256%Z]))])
    (bad_string "'landshark_control_base_velocity': '.header.frame_id'").
Proof. vm_compute. reflexivity. Qed.

Example refuse_negative_byte:
  refused (with_strings [("landshark_control_base_velocity", (frame_id, [(-1)%Z]))])
    (bad_string "'landshark_control_base_velocity': '.header.frame_id'").
Proof. vm_compute. reflexivity. Qed.

Example refuse_subscribed:
  refused (with_strings [("landshark_gps_velocity", (frame_id, base_link))])
    (bad_string "'landshark_gps_velocity': '.header.frame_id'").
Proof. vm_compute. reflexivity. Qed.

Example refuse_not_string:
  refused (with_strings [("landshark_control_base_velocity", ([PField "header"], base_link))])
    (bad_string "'landshark_control_base_velocity': '.header'").
Proof. vm_compute. reflexivity. Qed.

Example refuse_twice:
  refused (with_strings [("landshark_control_base_velocity", (frame_id, base_link));
                         ("landshark_control_base_velocity", (frame_id, []))])
    "Generator: constant string given twice: 'landshark_control_base_velocity.header.frame_id'".
Proof. vm_compute. reflexivity. Qed.

(** A string struct of another shape (no [truncated]) is not a string. *)
Example refuse_not_string_struct:
  refused {| nm_name := nm_name framed; nm_period_ms := nm_period_ms framed; nm_ctrl := nm_ctrl framed;
             nm_in_var := nm_in_var framed; nm_in_struct := nm_in_struct framed;
             nm_inputs := nm_inputs framed; nm_out_var := nm_out_var framed;
             nm_out_struct := nm_out_struct framed; nm_outputs := nm_outputs framed;
             nm_msgs := [ros_time; mkmsgdef "ros_string16" [("len", FTprim Puint32);
                                                           ("data", FTarray (FTprim Puint8) 16)];
                         header_framed; geometry_msgs_Vector3; geometry_msgs_Twist;
                         geometry_msgs_TwistStamped];
             nm_topics := nm_topics framed; nm_inrels := nm_inrels framed;
             nm_outrels := nm_outrels framed; nm_timeouts := []; nm_fallbacks := []; nm_drels := [];
             nm_stamps := []; nm_stamp_from := []; nm_strings := nm_strings framed |}
    (bad_string "'landshark_control_base_velocity': '.header.frame_id'").
Proof. vm_compute. reflexivity. Qed.

(** An output relation writing into the string conflicts with it. *)
Example refuse_overwritten:
  refused {| nm_name := nm_name framed; nm_period_ms := nm_period_ms framed; nm_ctrl := nm_ctrl framed;
             nm_in_var := nm_in_var framed; nm_in_struct := nm_in_struct framed;
             nm_inputs := nm_inputs framed; nm_out_var := nm_out_var framed;
             nm_out_struct := nm_out_struct framed; nm_outputs := [("Out1", FTprim Pfloat64); ("Len", FTprim Puint32)];
             nm_msgs := nm_msgs framed; nm_topics := nm_topics framed; nm_inrels := nm_inrels framed;
             nm_outrels := nm_outrels framed ++
                           [mkoutrel "Len" "landshark_control_base_velocity" (frame_id ++ [PField "len"])];
             nm_timeouts := []; nm_fallbacks := []; nm_drels := [];
             nm_stamps := []; nm_stamp_from := []; nm_strings := nm_strings framed |}
    (bad_string "'landshark_control_base_velocity': '.header.frame_id'").
Proof. vm_compute. reflexivity. Qed.

(** ** A run *)

Definition f_one : float64 := float64_of_bits 0x3FF0000000000000.

Definition ce : composite_env := composites framed.
Definition TS : type := Tstruct "geometry_msgs_TwistStamped".

Definition msg_x (x : float64) : mval :=
  match mval_set (zero_mval ce TS) (path_steps twist_x) (MVscalar (Vfloat x)) with
  | Some v => v
  | None => MVscalar Vundef
  end.

Definition y_one : mval := MVstruct [("Out1", MVscalar (Vfloat f_one))].

Definition ctx : ros_context unit :=
  mkctx (fun k => match k with
                  | O => [mkarrival (tp_name left_wheel) (msg_x f_one) 7]
                  | _ => []
                  end)
        (fun k => (Z.of_nat k * 1000000000)%Z) tt (fun _ _ => (tt, y_one)) Ros1.

Lemma ctx_arrivals_wt: arrivals_wt framed ctx.
Proof.
  intros k a tp H Htp _. apply mval_typecheck_iff.
  destruct k as [|k]; simpl in H; [|contradiction].
  destruct H as [<-|[]]. simpl in Htp.
  destruct Htp as [<-|[<-|[<-|[]]]]; vm_compute; reflexivity.
Qed.

Lemma ctx_controller_wt: controller_wt framed ctx.
Proof. intros s u. apply mval_typecheck_iff. vm_compute. reflexivity. Qed.

Definition int_at (mv : mval) (p : path) : option Z :=
  match mval_get mv (path_steps p) with Some (MVscalar (Vint n)) => Some n | _ => None end.

(** The 18 leaves of the published [frame_id]: [len], [truncated], the
    16 bytes. *)
Definition string_leaves : list path :=
  [frame_id ++ [PField "len"]; frame_id ++ [PField "truncated"]]
  ++ map (fun i => frame_id ++ [PField "data"; PIndex i]) (zrange 16).

Definition strings_of (t : trace) : list (list (option Z)) :=
  flat_map (fun e => match e with
                     | Epublish _ mv => [map (int_at mv) string_leaves]
                     | _ => []
                     end) t.

(** What T2 says: length 9, [truncated] 0, the 9 bytes, 7 zeros. *)
Definition leaves_expected : list (option Z) :=
  map Some ([9; 0]%Z ++ base_link ++ repeat 0%Z 7).

Example framed_run:
  match run_trace 2000 framed_prog ctx 2 with
  | Some t => strings_of t = [leaves_expected; leaves_expected]
  | None => False
  end.
Proof. vm_compute. reflexivity. Qed.

(** ** Mutants *)

Lemma strings_of_app: forall t1 t2 : trace, strings_of (t1 ++ t2) = strings_of t1 ++ strings_of t2.
Proof. intros; unfold strings_of; apply flat_map_app. Qed.

(** [published_value] fixes the 18 leaves. *)
Lemma published_leaves:
  forall y now g mv, published_value framed y now g base mv -> map (int_at mv) string_leaves = leaves_expected.
Proof.
  intros y now g mv (_ & _ & _ & STR & Z).
  destruct (STR frame_id base_link (or_introl eq_refl)) as [Len Data].
  assert (ZL: forall lp, resolve (nm_msgs framed) (FTmsg "geometry_msgs_TwistStamped") lp = Some (FTprim Puint8)
                        \/ resolve (nm_msgs framed) (FTmsg "geometry_msgs_TwistStamped") lp = Some (FTprim Pbool) ->
              lp <> frame_id ++ [PField "len"] ->
              (forall i, (i < 9)%nat -> lp <> frame_id ++ [PField "data"; PIndex (Z.of_nat i)]) ->
              int_at mv lp = Some 0%Z).
  { intros lp R N1 N2. unfold int_at.
    destruct R as [R|R]; rewrite (Z lp _ R); try reflexivity.
    all: try (match goal with |- forall _ : outrel, _ => idtac end;
              intros o Ho Eo; simpl in Ho; destruct Ho as [Ho|[]]; subst o; intros E; simpl in E; subst lp;
              vm_compute in R; discriminate R).
    all: try (intros sp E; vm_compute in E; discriminate E).
    all: intros sp bs H; simpl in H; destruct H as [E|[]]; inversion E; subst sp bs;
         split; [exact N1|intros i Hi; apply N2; exact Hi]. }
  assert (DL: int_at mv (frame_id ++ [PField "len"]) = Some 9%Z) by (unfold int_at; rewrite Len; reflexivity).
  assert (DT: int_at mv (frame_id ++ [PField "truncated"]) = Some 0%Z).
  { apply ZL; [right; reflexivity|intros E; discriminate E|].
    intros i _ E. apply app_inv_head in E. discriminate E. }
  assert (DD: forall i b, nth_error base_link i = Some b ->
              int_at mv (frame_id ++ [PField "data"; PIndex (Z.of_nat i)]) = Some b).
  { intros i b H. unfold int_at. rewrite (Data i b H). reflexivity. }
  assert (DZ: forall k, (9 <= k < 16)%nat -> int_at mv (frame_id ++ [PField "data"; PIndex (Z.of_nat k)]) = Some 0%Z).
  { intros k Hk. apply ZL.
    - left. destruct k as [|[|[|[|[|[|[|[|[|[|[|[|[|[|[|[|k]]]]]]]]]]]]]]]]; try lia; reflexivity.
    - intros E. apply app_inv_head in E. discriminate E.
    - intros i Hi E. apply app_inv_head in E. inversion E. lia. }
  pose proof (DD 0%nat _ eq_refl) as D0. pose proof (DD 1%nat _ eq_refl) as D1.
  pose proof (DD 2%nat _ eq_refl) as D2. pose proof (DD 3%nat _ eq_refl) as D3.
  pose proof (DD 4%nat _ eq_refl) as D4. pose proof (DD 5%nat _ eq_refl) as D5.
  pose proof (DD 6%nat _ eq_refl) as D6. pose proof (DD 7%nat _ eq_refl) as D7.
  pose proof (DD 8%nat _ eq_refl) as D8.
  pose proof (DZ 9%nat ltac:(lia)) as Z9. pose proof (DZ 10%nat ltac:(lia)) as Z10.
  pose proof (DZ 11%nat ltac:(lia)) as Z11. pose proof (DZ 12%nat ltac:(lia)) as Z12.
  pose proof (DZ 13%nat ltac:(lia)) as Z13. pose proof (DZ 14%nat ltac:(lia)) as Z14.
  pose proof (DZ 15%nat ltac:(lia)) as Z15.
  cbn -[int_at] in DL, DT, D0, D1, D2, D3, D4, D5, D6, D7, D8, Z9, Z10, Z11, Z12, Z13, Z14, Z15.
  unfold string_leaves, leaves_expected.
  change (zrange 16) with [0;1;2;3;4;5;6;7;8;9;10;11;12;13;14;15]%Z. cbn -[int_at].
  rewrite DL, DT, D0, D1, D2, D3, D4, D5, D6, D7, D8, Z9, Z10, Z11, Z12, Z13, Z14, Z15. reflexivity.
Qed.

(** The string is sent as the glue wrote it: its length (9) is within
    its capacity (16), and the bytes past the length are zero
    ([sent_sequence]). *)
Lemma sent_leaves:
  forall mv, mval_has_type (composites framed) (Tstruct (tp_msg base)) mv ->
  map (int_at mv) string_leaves = leaves_expected ->
  map (int_at (sent framed base mv)) string_leaves = leaves_expected.
Proof.
  intros mv T H.
  assert (DL: int_at mv (frame_id ++ [PField "len"]) = Some 9%Z) by exact (f_equal (fun l => nth 0 l None) H).
  assert (DT: int_at mv (frame_id ++ [PField "truncated"]) = Some 0%Z) by exact (f_equal (fun l => nth 1 l None) H).
  assert (DZ: forall j, (9 <= j < 16)%Z -> int_at mv (frame_id ++ [PField "data"; PIndex j]) = Some 0%Z).
  { intros j Hj.
    assert (E: j = 9%Z \/ j = 10%Z \/ j = 11%Z \/ j = 12%Z \/ j = 13%Z \/ j = 14%Z \/ j = 15%Z) by lia.
    destruct E as [->|[->|[->|[->|[->|[->| ->]]]]]].
    - exact (f_equal (fun l => nth 11 l None) H).
    - exact (f_equal (fun l => nth 12 l None) H).
    - exact (f_equal (fun l => nth 13 l None) H).
    - exact (f_equal (fun l => nth 14 l None) H).
    - exact (f_equal (fun l => nth 15 l None) H).
    - exact (f_equal (fun l => nth 16 l None) H).
    - exact (f_equal (fun l => nth 17 l None) H). }
  destruct (mval_get_has_type _ (path_steps (frame_id ++ [PField "len"])) _ _ (Tint I32 Unsigned) T
              ltac:(vm_compute; reflexivity)) as (x & Gx & Tx).
  inversion Tx as [? v _ Tv| |]; subst.
  assert (GL: mval_get mv (path_steps (frame_id ++ [PField "len"])) = Some (MVscalar (Vint 9))).
  { rewrite Gx. unfold int_at in DL. rewrite Gx in DL. destruct v; try discriminate. inversion DL; subst. reflexivity. }
  destruct (sent_sequence framed base mv frame_id "ros_string16" 16 (Tint I8 Unsigned) 9 T
              ltac:(repeat split; vm_compute; reflexivity) GL) as (L & Tr & D).
  assert (Ex: forall j, (0 <= j < 16)%Z ->
              int_at (sent framed base mv) (frame_id ++ [PField "data"; PIndex j])
              = int_at mv (frame_id ++ [PField "data"; PIndex j])).
  { intros j Hj. unfold int_at. rewrite (D j Hj).
    destruct (j <? Z.min 9 16)%Z eqn:Lj; [reflexivity|].
    apply Z.ltb_ge in Lj. change (Z.min 9 16) with 9%Z in Lj.
    assert (Hz: int_at mv (frame_id ++ [PField "data"; PIndex j]) = Some 0%Z) by (apply DZ; lia).
    unfold int_at in Hz. rewrite Hz. reflexivity. }
  rewrite <- H. unfold string_leaves. cbn [map app].
  f_equal; [unfold int_at; rewrite L, GL; reflexivity|].
  f_equal; [unfold int_at; rewrite Tr; cbn; symmetry; exact DT|].
  rewrite !map_map. apply map_ext_in. intros j Hj. apply Ex.
  unfold zrange in Hj. apply in_map_iff in Hj. destruct Hj as (k & <- & Hk). apply in_seq in Hk. lia.
Qed.

Lemma run_ok_strings:
  forall n t, run_ok framed ctx n t -> strings_of t = repeat leaves_expected n.
Proof.
  intros n t (s & evs & _ & -> & C).
  rewrite strings_of_app. replace (strings_of (start_events framed)) with (@nil (list (option Z)))
    by (vm_compute; reflexivity).
  simpl app.
  assert (G: forall k, (k <= n)%nat -> strings_of (concat (map evs (seq (n - k) k))) = repeat leaves_expected k).
  { induction k as [|k IH]; intros Hk; simpl; auto.
    rewrite strings_of_app.
    destruct (C (n - S k)%nat ltac:(lia)) as (u & y & mvs & E & _ & _ & PV).
    rewrite E. simpl published in PV.
    inversion PV as [|tp mv tps mvs' P F]; subst. inversion F; subst.
    assert (S1: strings_of (Estep u y :: publish_events framed (published framed) [mv] ++ [Esleep (nm_period_ms framed)])
                = [map (int_at (sent framed base mv)) string_leaves]) by reflexivity.
    rewrite S1, (sent_leaves mv (proj1 P) (published_leaves _ _ _ _ P)). simpl app. f_equal.
    replace (S (n - S k)) with (n - k)%nat by lia. apply IH. lia. }
  specialize (G n (le_n n)). rewrite Nat.sub_diag in G. exact G.
Qed.

Definition leaves_eq_dec : forall a b : list (option Z), {a = b} + {a <> b}.
Proof. decide equality; decide equality; apply Z.eq_dec. Defined.

Definition check (p : program) (n : nat) : bool :=
  match run_trace 2000 p ctx n with
  | Some t => if list_eq_dec leaves_eq_dec (strings_of t) (repeat leaves_expected n) then true else false
  | None => true
  end.

Lemma refute: forall p n, check p n = false -> ~ node_ddc framed p.
Proof.
  intros p n H D. unfold check in H.
  destruct (run_trace 2000 p ctx n) as [t|] eqn:R; [|discriminate].
  destruct (D unit ctx n ctx_arrivals_wt ctx_controller_wt) as [_ All].
  rewrite (run_ok_strings n t (All t (run_trace_sound _ ctx 2000 p n t R))) in H.
  destruct (list_eq_dec leaves_eq_dec (repeat leaves_expected n) (repeat leaves_expected n)); congruence.
Qed.

(** The generated program passes (as T2 says it must). *)
Example framed_passes: check framed_prog 2 = true.
Proof. vm_compute. reflexivity. Qed.

(** The output glue's string stores changed by [g]. *)
Definition on_strings (g : statement -> statement) (p : program) : program :=
  mkprogram (prog_types p)
    (map (fun d : ident * globdef => if string_dec (fst d) "output_glue_landshark_control_base_velocity"
                   then match snd d with
                        | Gfun (Internal f) =>
                            (fst d, Gfun (Internal (mkfunction (fn_return f) (fn_params f) (fn_vars f)
                                                                (fn_temps f)
                                                                (match fn_body f with
                                                                 | Ssequence pre strs => Ssequence pre (g strs)
                                                                 | b => b
                                                                 end))))
                        | _ => d
                        end
                   else d) (prog_defs p))
    (prog_main p).

(** The stores of [frame_id] with the model's store list changed by [h]. *)
Definition stores_of (h : list (path * prim * Z) -> list (path * prim * Z)) : statement :=
  seq_of (map (const_store framed "geometry_msgs_TwistStamped") (h (string_stores frame_id base_link))).

(** (t1) the length off by one *)
Definition m_len_off : program :=
  on_strings (fun _ => stores_of (fun l => match l with (lp, q, n) :: r => (lp, q, (n + 1)%Z) :: r | [] => [] end))
             framed_prog.
Theorem m_len_off_refuted: ~ node_ddc framed m_len_off.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (t2) a wrong byte: ['B'] for ['b'] *)
Definition m_wrong_byte : program :=
  on_strings (fun _ => seq_of (map (const_store framed "geometry_msgs_TwistStamped")
                                   (string_stores frame_id (66%Z :: tl base_link)))) framed_prog.
Theorem m_wrong_byte_refuted: ~ node_ddc framed m_wrong_byte.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (t3) the last byte left out (an off-by-one bound on the bytes) *)
Definition m_last_missing : program :=
  on_strings (fun _ => stores_of (fun l => removelast l)) framed_prog.
Theorem m_last_missing_refuted: ~ node_ddc framed m_last_missing.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** (t4) the string's length stored as its capacity (16) instead of its
    number of bytes (9): the string is sent with 7 zero bytes more.  (A
    byte stored past the length is not a bug any more: the environment,
    like the wrapper, sends only the first [len] bytes, so such a program
    publishes the same messages and satisfies T2; [past_length_sent]
    below shows it.) *)
Definition m_len_capacity : program :=
  on_strings (fun _ => stores_of (fun l => match l with (lp, q, _) :: r => (lp, q, 16%Z) :: r | [] => [] end))
             framed_prog.
Theorem m_len_capacity_refuted: ~ node_ddc framed m_len_capacity.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.

(** A byte stored past the length is not sent: the run publishes exactly
    what T2 prescribes. *)
Definition m_past_length : program :=
  on_strings (fun _ => stores_of (fun l => l ++ [(frame_id ++ [PField "data"; PIndex 9], Puint8, 120%Z)]))
             framed_prog.
Example past_length_sent: check m_past_length 2 = true.
Proof. vm_compute. reflexivity. Qed.

(** (t5) the strings written before the zeroing, which erases them *)
Definition m_strings_first : program :=
  mkprogram (prog_types framed_prog)
    (map (fun d : ident * globdef => if string_dec (fst d) "output_glue_landshark_control_base_velocity"
                   then match snd d with
                        | Gfun (Internal f) =>
                            (fst d, Gfun (Internal (mkfunction (fn_return f) (fn_params f) (fn_vars f)
                                                                (fn_temps f)
                                                                (match fn_body f with
                                                                 | Ssequence pre strs => Ssequence strs pre
                                                                 | b => b
                                                                 end))))
                        | _ => d
                        end
                   else d) (prog_defs framed_prog))
    (prog_main framed_prog).
Theorem m_strings_first_refuted: ~ node_ddc framed m_strings_first.
Proof. apply (refute _ 1). vm_compute. reflexivity. Qed.
