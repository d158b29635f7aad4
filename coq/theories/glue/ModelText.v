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
    input FIELD PRIM                      (one per controller input, in C order)
    outputs VAR STRUCT
    output FIELD PRIM
    message STRUCT                        (one per message definition)
    field NAME FTYPE                      (FTYPE: PRIM | msg STRUCT | array N FTYPE)
    topic ROSNAME CNAME subscribe|publish TYPE QUEUE   (TYPE: the ROS type pkg/Type)
    input_relation TOPIC PATH INPUT       (PATH: twist.linear.x, covariance[35])
    output_relation OUTPUT TOPIC PATH
>>
*)

From Coq Require Import String List ZArith.
From ROSGen Require Import Syntax Printer NodeModel.
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

Definition field_lines (kw : string) (fs : list (ident * prim)) : list string :=
  map (fun fp => kw ++ " " ++ fst fp ++ " " ++ prim_name (snd fp)) fs.

Definition msg_lines (md : msgdef) : list string :=
  ("message " ++ md_name md)
  :: map (fun f => "field " ++ fst f ++ " " ++ ftype_text (snd f)) (md_fields md).

Definition topic_line (t : topic) : string :=
  "topic " ++ tp_name t ++ " " ++ tp_cname t ++ " " ++ direction_text (tp_dir t)
  ++ " " ++ tp_type t ++ " " ++ string_of_Z (Z.of_nat (tp_queue t)).

Definition inrel_line (r : inrel) : string :=
  "input_relation " ++ ir_topic r ++ " " ++ path_text (ir_path r) ++ " " ++ ir_input r.

Definition outrel_line (r : outrel) : string :=
  "output_relation " ++ or_output r ++ " " ++ or_topic r ++ " " ++ path_text (or_path r).

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
  ++ map outrel_line (nm_outrels m).

(** The text: every line followed by a newline. *)
Definition print_model (m : node_model) : string := concat_lines (model_lines m).

(** Every relation, topic and field of the model has its own line: the
    text determines the lists of relations and topics, in order.  (The
    number of lines is the number of items; a dropped or added relation
    changes it.) *)
