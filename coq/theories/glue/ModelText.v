(** * The node model as canonical text *)

(** [print_model m] is the model that a per-node theorem is about, as
    text: one item per line, single spaces, in model order.  The per-node
    file prints it from its [model] term through the same extraction path
    as the C, and [pyrosgen generate] compares it, line by line, with the
    front end's reading of the YAML file (DESIGN.md section 7): a model
    term that says something else than the user's file (an emitter bug, an
    edited [.v]) is refused before anything is written.

    The grammar (every name was checked by [Wellformed]: no spaces, no
    line breaks; a topic's message struct is not printed, since
    [Wellformed.topic_ok] makes it the struct of its ROS type,
    [ros_type_struct]: [pkg/Type] gives [pkg_Type]):
<<
    pyrosgen-model 1
    node NAME
    period_ms N
    controller NAME
    inputs VAR STRUCT
    input FIELD CTYPE                     (one per controller input, in C order;
                                           CTYPE: PRIM | array N PRIM)
    outputs VAR STRUCT
    output FIELD CTYPE
    message STRUCT                        (one per message definition)
    field NAME FTYPE                      (FTYPE: PRIM | msg STRUCT | array N FTYPE)
    topic ROSNAME CNAME subscribe|publish TYPE QUEUE   (TYPE: the ROS type pkg/Type)
    input_relation TOPIC PATH INPUT       (PATH: twist.linear.x, covariance[35];
                                           INPUT: In1, or Scan[540] for an element)
    output_relation OUTPUT TOPIC PATH     (OUTPUT: Out1, or Cmd[3])
    timeout TOPIC MS                      (rule 4.12, in topic order)
    fallback INPUT VALUE                  (VALUE: decimal integer, or a float's
                                           bits: 0x and 16 or 8 hex digits)
    derived_input TOPIC KIND INPUT        (KIND: is_new | received | age_ms)
    stamp TOPIC PATH                      (rule 4.13)
    stamp_from TOPIC SOURCE PATH          (rule 4.13)
    string TOPIC PATH BYTES               (rule 4.14; BYTES: the decimal bytes
                                           joined by commas, [-] if none)
>>
    TOPIC is a topic's C name.
*)

From Coq Require Import String Ascii List ZArith Bool.
From Flocq Require Import IEEE754.Bits.
From ROSGen Require Import FloatBits Syntax Values Printer NodeModel.
Import ListNotations.
Local Open Scope string_scope.

(** A field type. *)
Fixpoint ftype_text (t : ftype) : string :=
  match t with
  | FTprim q => prim_name q
  | FTmsg m => "msg " ++ m
  | FTarray t' n => "array " ++ string_of_Z n ++ " " ++ ftype_text t'
  end.

(** A path: [.f] for a field (no dot first), [[i]] for an index. *)
Fixpoint path_text_rec (first : bool) (p : NodeModel.path) : string :=
  match p with
  | [] => ""
  | PField f :: p' => (if first then "" else ".") ++ f ++ path_text_rec false p'
  | PIndex i :: p' => "[" ++ string_of_Z i ++ "]" ++ path_text_rec false p'
  end.

Definition path_text (p : NodeModel.path) : string := path_text_rec true p.

Definition direction_text (d : direction) : string :=
  match d with Subscribe => "subscribe" | Publish => "publish" end.

Definition field_lines (kw : string) (fs : list (ident * ftype)) : list string :=
  map (fun ft => kw ++ " " ++ fst ft ++ " " ++ ftype_text (snd ft)) fs.

Definition msg_lines (md : msgdef) : list string :=
  ("message " ++ md_name md)
  :: map (fun f => "field " ++ fst f ++ " " ++ ftype_text (snd f)) (md_fields md).

Definition topic_line (t : topic) : string :=
  "topic " ++ tp_name t ++ " " ++ tp_cname t ++ " " ++ direction_text (tp_dir t)
  ++ " " ++ tp_type t ++ " " ++ string_of_Z (Z.of_nat (tp_queue t)).

Definition inrel_line (r : inrel) : string :=
  "input_relation " ++ ir_topic r ++ " " ++ path_text (ir_path r) ++ " " ++ ir_input r
  ++ path_text_rec false (ir_elem r).

Definition outrel_line (r : outrel) : string :=
  "output_relation " ++ or_output r ++ path_text_rec false (or_elem r) ++ " " ++ or_topic r
  ++ " " ++ path_text (or_path r).

(** A constant: an integer in decimal, a float as its IEEE bit pattern
    (also the diagram text's notation, [DiagramText]). *)
Definition val_text (v : val) : string :=
  match v with
  | Vint n | Vlong n => string_of_Z n
  | Vfloat f => "0x" ++ hex_digits 16 (bits_of_b64 f)
  | Vsingle f => "0x" ++ hex_digits 8 (bits_of_b32 f)
  | Vundef => "undef"
  | Vptr _ _ | Vfptr _ => "pointer"
  end.

Definition derived_text (k : derived) : string :=
  match k with Dis_new => "is_new" | Dreceived => "received" | Dage_ms => "age_ms" end.

Definition timeout_line (t : ident * Z) : string :=
  "timeout " ++ fst t ++ " " ++ string_of_Z (snd t).

Definition fallback_line (f : ident * val) : string :=
  "fallback " ++ fst f ++ " " ++ val_text (snd f).

Definition drel_line (r : drel) : string :=
  "derived_input " ++ dr_topic r ++ " " ++ derived_text (dr_kind r) ++ " " ++ dr_input r.

Definition stamp_line (s : ident * NodeModel.path) : string :=
  "stamp " ++ fst s ++ " " ++ path_text (snd s).

Definition stamp_from_line (s : ident * (ident * NodeModel.path)) : string :=
  "stamp_from " ++ fst s ++ " " ++ fst (snd s) ++ " " ++ path_text (snd (snd s)).

(** The bytes of a constant string: [98,97] or [-]. *)
Definition bytes_text (bs : list Z) : string :=
  match bs with
  | [] => "-"
  | b :: rest => fold_left (fun acc x => acc ++ "," ++ string_of_Z x) rest (string_of_Z b)
  end.

Definition string_line (s : ident * (NodeModel.path * list Z)) : string :=
  "string " ++ fst s ++ " " ++ path_text (fst (snd s)) ++ " " ++ bytes_text (snd (snd s)).

(** The lines of the model. *)
Definition model_lines (m : node_model) : list string :=
  [ "pyrosgen-model 1";
    "node " ++ nm_name m;
    "period_ms " ++ string_of_Z (nm_period_ms m);
    "controller " ++ nm_ctrl m;
    "inputs " ++ nm_in_var m ++ " " ++ nm_in_struct m ]
  ++ field_lines "input" (nm_inputs m)
  ++ [ "outputs " ++ nm_out_var m ++ " " ++ nm_out_struct m ]
  ++ field_lines "output" (nm_outputs m)
  ++ flat_map msg_lines (nm_msgs m)
  ++ map topic_line (nm_topics m)
  ++ map inrel_line (nm_inrels m)
  ++ map outrel_line (nm_outrels m)
  ++ map timeout_line (nm_timeouts m)
  ++ map fallback_line (nm_fallbacks m)
  ++ map drel_line (nm_drels m)
  ++ map stamp_line (nm_stamps m)
  ++ map stamp_from_line (nm_stamp_from m)
  ++ map string_line (nm_strings m).

(** The text: every line followed by a newline. *)
Definition print_model (m : node_model) : string := concat_lines (model_lines m).

(** ** The text determines the lines, and the topic and relation lines *)

(** Every item of the model has its own line.  When no line contains a
    line feed ([lines_ok]; the names that [Wellformed] accepts contain
    none, and the LandShark text is checked in
    tests/ModelTextExamples.v), the text determines its lines, in order
    ([print_model_lines]), and so the lines of the topics, of the input
    relations and of the output relations, in model order
    ([print_model_items]): a model with a topic or relation dropped,
    added, reordered or with another line has another text. *)

Definition newline_char : ascii := ascii_of_byte Byte.x0a.

Fixpoint no_newline (s : string) : bool :=
  match s with
  | EmptyString => true
  | String c s' => negb (Ascii.eqb c newline_char) && no_newline s'
  end.

Definition lines_ok (m : node_model) : bool := forallb no_newline (model_lines m).

Lemma str_app_nil: forall s, (s ++ "")%string = s.
Proof. induction s as [|c s IH]; simpl; [|rewrite IH]; reflexivity. Qed.

Lemma str_app_assoc: forall a b c, ((a ++ b) ++ c)%string = (a ++ (b ++ c))%string.
Proof. induction a as [|x a IH]; intros b c; simpl; [|rewrite IH]; reflexivity. Qed.

Lemma concat_lines_cons:
  forall s l, concat_lines (s :: l) = (s ++ newline ++ concat_lines l)%string.
Proof.
  intros s l. unfold concat_lines. destruct l as [|s' l]; cbn [map String.concat append].
  - rewrite str_app_nil. reflexivity.
  - rewrite str_app_assoc. reflexivity.
Qed.

Lemma split_newline:
  forall s1 s2 r1 r2, no_newline s1 = true -> no_newline s2 = true ->
  (s1 ++ newline ++ r1 = s2 ++ newline ++ r2)%string -> s1 = s2 /\ r1 = r2.
Proof.
  induction s1 as [|c1 s1 IH]; intros s2 r1 r2 N1 N2 E; destruct s2 as [|c2 s2]; simpl in *.
  - inversion E; auto.
  - inversion E; subst. apply andb_true_iff in N2. destruct N2 as [N2 _].
    rewrite Ascii.eqb_refl in N2. discriminate.
  - inversion E; subst. apply andb_true_iff in N1. destruct N1 as [N1 _].
    rewrite Ascii.eqb_refl in N1. discriminate.
  - inversion E; subst. apply andb_true_iff in N1, N2.
    destruct (IH s2 r1 r2 (proj2 N1) (proj2 N2) H1) as [-> ->]; auto.
Qed.

Lemma concat_lines_inj:
  forall l1 l2, forallb no_newline l1 = true -> forallb no_newline l2 = true ->
  concat_lines l1 = concat_lines l2 -> l1 = l2.
Proof.
  induction l1 as [|s1 l1 IH]; intros l2 N1 N2 E; destruct l2 as [|s2 l2]; auto.
  - rewrite concat_lines_cons in E. destruct s2; discriminate E.
  - rewrite concat_lines_cons in E. destruct s1; discriminate E.
  - rewrite !concat_lines_cons in E. simpl in N1, N2. apply andb_true_iff in N1, N2.
    destruct (split_newline _ _ _ _ (proj1 N1) (proj1 N2) E) as [-> E'].
    f_equal. apply IH; tauto.
Qed.

Theorem print_model_lines:
  forall m1 m2, lines_ok m1 = true -> lines_ok m2 = true ->
  print_model m1 = print_model m2 -> model_lines m1 = model_lines m2.
Proof. intros m1 m2 N1 N2 E. apply concat_lines_inj; auto. Qed.

(** The lines of one kind, recognised by their keyword. *)
Definition lines_of (kw : string) (m : node_model) : list string :=
  filter (prefix (kw ++ " ")) (model_lines m).

Lemma prefix_app: forall p s, prefix p (p ++ s) = true.
Proof.
  induction p as [|c p IH]; intros s; simpl; [destruct s; auto|].
  destruct (ascii_dec c c); [apply IH|congruence].
Qed.

Lemma filter_map_all:
  forall (A : Type) (f : A -> string) (P : string -> bool) l,
  (forall x, P (f x) = true) -> filter P (map f l) = map f l.
Proof. induction l as [|x l IH]; intros H; simpl; auto. rewrite H, IH; auto. Qed.

Lemma filter_map_none:
  forall (A : Type) (f : A -> string) (P : string -> bool) l,
  (forall x, P (f x) = false) -> filter P (map f l) = [].
Proof. induction l as [|x l IH]; intros H; simpl; auto. rewrite H, IH; auto. Qed.

Lemma filter_none:
  forall (P : string -> bool) l, (forall s, In s l -> P s = false) -> filter P l = [].
Proof.
  induction l as [|s l IH]; intros H; simpl; auto.
  rewrite H by (simpl; auto). apply IH. intros; apply H; simpl; auto.
Qed.

(** A line of another kind does not start with [kw ]. *)
Local Ltac other_kind :=
  intros ? H; unfold field_lines, msg_lines in *;
  repeat match goal with
  | H : In _ (map _ _) |- _ => apply in_map_iff in H; destruct H as (? & <- & _)
  | H : In _ (flat_map _ _) |- _ => apply in_flat_map in H; destruct H as (? & _ & H)
  | H : In _ (_ :: _) |- _ => destruct H as [<-|H]
  | H : In _ [] |- _ => destruct H
  end; reflexivity.

Local Ltac lines_kind f :=
  intros m; unfold lines_of, model_lines; rewrite !filter_app;
  rewrite (filter_map_all _ f) by (intros; apply prefix_app);
  repeat (rewrite filter_none by other_kind);
  rewrite ?app_nil_l, ?app_nil_r; reflexivity.

Lemma lines_topic: forall m, lines_of "topic" m = map topic_line (nm_topics m).
Proof. lines_kind topic_line. Qed.

Lemma lines_inrel: forall m, lines_of "input_relation" m = map inrel_line (nm_inrels m).
Proof. lines_kind inrel_line. Qed.

Lemma lines_outrel: forall m, lines_of "output_relation" m = map outrel_line (nm_outrels m).
Proof. lines_kind outrel_line. Qed.

(** Two models without line feeds in their lines and with the same text
    have the same lines, the same topic lines, input relation lines and
    output relation lines, in order (so as many topics and relations). *)
Theorem print_model_items:
  forall m1 m2, lines_ok m1 = true -> lines_ok m2 = true -> print_model m1 = print_model m2 ->
     model_lines m1 = model_lines m2
  /\ map topic_line (nm_topics m1) = map topic_line (nm_topics m2)
  /\ map inrel_line (nm_inrels m1) = map inrel_line (nm_inrels m2)
  /\ map outrel_line (nm_outrels m1) = map outrel_line (nm_outrels m2).
Proof.
  intros m1 m2 N1 N2 E. assert (L: model_lines m1 = model_lines m2) by (apply print_model_lines; auto).
  rewrite <- !lines_topic, <- !lines_inrel, <- !lines_outrel. unfold lines_of. rewrite L. auto.
Qed.
