(** * A block diagram as canonical text *)

(** [print_diagram d] is the diagram that a node's controller theorems
    are about, as text, one item per line, single spaces, in the order of
    the diagram's lists.  The per-node file extracts it next to the
    controller's C, and [pyrosgen generate] compares it line by line with
    the front end's reading of the model's [controller.blocks]
    ([pyrosgen/proof/modeltext.py], DESIGN.md section 7), as it does for
    the model ([ModelText]): a diagram term that says something else than
    the user's blocks (an emitter bug, an edited [.v]) is refused before
    anything is written.  The certificate shows this text.

    The grammar (names were checked by the front end and by [dg_wf]'s
    distinctness; constants of an integer type or [bool] in decimal, of a
    float type as their IEEE bit pattern, [0x] and 16 or 8 hex digits):
<<
    pyrosgen-diagram 1
    controller NAME
    inputs VAR STRUCT
    input FIELD PRIM                       (dg_inputs, in C order)
    outputs VAR STRUCT
    output FIELD PRIM
    states VAR STRUCT
    state NAME PRIM INIT INPUT delay
    state NAME PRIM INIT INPUT integrator KT [LOWER UPPER]
    eq SIGNAL PRIM BLOCK                   (dg_eqs, in evaluation order)
    out FIELD SIGNAL                       (dg_outs)
>>
    where BLOCK is one of [inport FIELD], [state NAME], [const V],
    [gain K A], [sum ±A ±B ...], [product A B], [divide A B], [abs A],
    [min A ...], [max A ...], [saturation LOWER UPPER A],
    [relational OP PRIM A B] (OP one of [== != < > <= >=]),
    [logic OP A ...] (OP one of [AND OR NAND NOR XOR NOT]),
    [switch CRIT PRIM THRESHOLD A C B] (CRIT one of [>= > ~=0]). *)

From Coq Require Import String List ZArith Bool.
From Flocq Require Import IEEE754.Bits.
From ROSGen Require Import FloatBits Syntax Values Printer NodeModel ModelText Diagram.
Import ListNotations.
Local Open Scope string_scope.

(** A constant, as the model text prints it ([ModelText.val_text]). *)
Definition val_text (v : val) : string := ModelText.val_text v.

Definition words (l : list string) : string := String.concat " " l.

Definition relop_text (op : relop) : string :=
  match op with Req => "==" | Rne => "!=" | Rlt => "<" | Rgt => ">" | Rle => "<=" | Rge => ">=" end.

Definition logop_text (op : logop) : string :=
  match op with
  | Land => "AND" | Lor => "OR" | Lnand => "NAND" | Lnor => "NOR" | Lxor => "XOR" | Lnot => "NOT"
  end.

Definition crit_text (c : switch_crit) : string :=
  match c with Cge => ">=" | Cgt => ">" | Cne0 => "~=0" end.

Definition block_text (b : dblock) : string :=
  match b with
  | Binport x => words ["inport"; x]
  | Bstate x => words ["state"; x]
  | Bconst c => words ["const"; val_text c]
  | Bgain k a => words ["gain"; val_text k; a]
  | Bsum terms => words ("sum" :: map (fun (t : bool * ident) => (if fst t then "+" else "-") ++ snd t) terms)
  | Bproduct a b => words ["product"; a; b]
  | Bdivide a b => words ["divide"; a; b]
  | Babs a => words ["abs"; a]
  | Bminmax ismax args => words ((if ismax then "max" else "min") :: args)
  | Bsaturation lo hi a => words ["saturation"; val_text lo; val_text hi; a]
  | Brelational op qa a b => words ["relational"; relop_text op; prim_name qa; a; b]
  | Blogical op args => words ("logic" :: logop_text op :: args)
  | Bswitch crit qc thr a c b =>
      words ["switch"; crit_text crit; prim_name qc; val_text thr; a; c; b]
  end.

Definition state_line (st : state_decl) : string :=
  words (["state"; st_name st; prim_name (st_type st); val_text (st_init st); st_input st]
         ++ match st_kind st with
            | Kdelay => ["delay"]
            | Kintegrator kt None => ["integrator"; val_text kt]
            | Kintegrator kt (Some (lo, hi)) => ["integrator"; val_text kt; val_text lo; val_text hi]
            end).

Definition diagram_lines (d : diagram) : list string :=
  ["pyrosgen-diagram 1";
   words ["controller"; dg_ctrl d];
   words ["inputs"; dg_in_var d; dg_in_struct d]]
  ++ map (fun fq => words ["input"; fst fq; prim_name (snd fq)]) (dg_inputs d)
  ++ [words ["outputs"; dg_out_var d; dg_out_struct d]]
  ++ map (fun fq => words ["output"; fst fq; prim_name (snd fq)]) (dg_outputs d)
  ++ [words ["states"; dg_state_var d; dg_state_struct d]]
  ++ map state_line (dg_states d)
  ++ map (fun e => words ["eq"; eq_sig e; prim_name (eq_type e); block_text (eq_block e)]) (dg_eqs d)
  ++ map (fun o => words ["out"; fst o; snd o]) (dg_outs d).

Definition print_diagram (d : diagram) : string := concat_lines (diagram_lines d).
