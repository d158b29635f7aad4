(** * The well-formedness rules of node models *)

(** [wf m] is the boolean conjunction of the rules of DESIGN.md section 4
    that a node model must satisfy for the generator to accept it, and
    [wf_check m] the same rules checked in the same order, failing with a
    message that names the first culprit ([Generatorproof.wf_check_wf]:
    [wf_check m = OK tt <-> wf m = true]).  [Generator.generate] runs
    [wf_check], then builds the program.

    The rules are about the model, and about the names that the
    generated program will use, so this file also fixes those names
    (section "Generated names", the lists [global_names],
    [local_names], [struct_names], [c_names]: they must be distinct,
    valid C identifiers), and the lookup tables ([make_tables]) that let
    the rules and the generator run in time linear in the size of the
    model. *)

From Coq Require Import String Ascii List ZArith Bool.
From ROSGen Require Import Errors Syntax Values Maps NodeModel.
Import ListNotations.

Local Open Scope string_scope.
Local Open Scope list_scope.
Local Open Scope error_monad_scope.

(** ** Generated names *)

(** Derived from a topic's C name [c]. *)
Definition msg_var (c : ident) : ident := (c ++ "_msg")%string.
Definition callback_name (c : ident) : ident := (c ++ "_callback")%string.
Definition subscribe_name (c : ident) : ident := ("ros_subscribe_" ++ c)%string.
Definition advertise_name (c : ident) : ident := ("ros_advertise_" ++ c)%string.
Definition publish_name (c : ident) : ident := ("ros_publish_" ++ c)%string.
Definition output_glue_name (c : ident) : ident := ("output_glue_" ++ c)%string.
Definition cmd_var (c : ident) : ident := (c ++ "_cmd")%string.

(** The clock of a timed subscribed topic [c] (rule 4.12): the receipt
    time of its newest message, whether a message arrived since the
    previous cycle, whether one ever arrived. *)
Definition time_var (c : ident) : ident := (c ++ "_time")%string.
Definition new_var (c : ident) : ident := (c ++ "_new")%string.
Definition rcvd_var (c : ident) : ident := (c ++ "_rcvd")%string.

(** Derived from the controller's name. *)
Definition init_name (m : node_model) : ident := (nm_ctrl m ++ "_initialize")%string.
Definition step_name (m : node_model) : ident := (nm_ctrl m ++ "_step")%string.

(** Fixed names. *)
Definition ros_init_name : ident := "ros_init".
Definition ros_ok_name : ident := "ros_ok".
Definition ros_spinOnce_name : ident := "ros_spinOnce".
Definition ros_rate_sleep_name : ident := "ros_rate_sleep".
Definition ros_now_name : ident := "ros_now".
Definition ros_time_sec_name : ident := "ros_time_sec".
Definition ros_time_nsec_name : ident := "ros_time_nsec".
Definition input_glue_name : ident := "input_glue".
Definition loop_name : ident := "loop".
Definition main_name : ident := "main".

(** Parameters and temporaries. *)
Definition msg_param : ident := "msg".
Definition command_param : ident := "command".
Definition ok_temp : ident := "_ok".
Definition now_temp : ident := "_now".
Definition age_temp : ident := "_age".

(** One temporary per C scalar type ([bool] and [uint8] share one). *)
Definition temp_name (q : prim) : ident :=
  match q with
  | Pbool | Puint8 => "_t_uchar"
  | Pint8 => "_t_schar"
  | Pint16 => "_t_short"
  | Puint16 => "_t_ushort"
  | Pint32 => "_t_int"
  | Puint32 => "_t_uint"
  | Pint64 => "_t_llong"
  | Puint64 => "_t_ullong"
  | Pfloat32 => "_t_float"
  | Pfloat64 => "_t_double"
  end.

(** All temporaries, each with its C type. *)
Definition all_temps : list (ident * type) :=
  [("_t_uchar", Tint I8 Unsigned); ("_t_schar", Tint I8 Signed);
   ("_t_short", Tint I16 Signed); ("_t_ushort", Tint I16 Unsigned);
   ("_t_int", Tint I32 Signed); ("_t_uint", Tint I32 Unsigned);
   ("_t_llong", Tlong Signed); ("_t_ullong", Tlong Unsigned);
   ("_t_float", Tfloat F32); ("_t_double", Tfloat F64)].

(** ** Lookup tables *)

(** Tables of the model's topics (by C name), controller fields, and output
    relations (by topic), built once per program so that generating and
    checking take time linear in the size of the model.
    [Generatorspec.tables_topics] etc. give their meaning in terms of
    [find_topic], [find_assoc] and [filter]. *)
Record tables : Type := mktables {
  tb_topics : ptree topic;
  tb_inputs : ptree ftype;
  tb_outputs : ptree ftype;
  tb_outrels : ptree (list outrel)
}.

(** The output relations grouped by topic, each group in model order. *)
Definition group_outrels (l : list outrel) : ptree (list outrel) :=
  fold_right (fun o t => tset (enc_string (or_topic o))
                              (o :: tget_default [] (enc_string (or_topic o)) t) t)
             PLeaf l.

Definition make_tables (m : node_model) : tables :=
  mktables (tmap_of_list enc_string (map (fun tp => (tp_cname tp, tp)) (nm_topics m)))
           (tmap_of_list enc_string (nm_inputs m))
           (tmap_of_list enc_string (nm_outputs m))
           (group_outrels (nm_outrels m)).

Section TABLES.

Variable tb : tables.

(** The topic with C name [c]. *)
Definition lookup_topic (c : ident) : option topic := tget (enc_string c) (tb_topics tb).

End TABLES.

(** ** Timed topics *)

(** [is_timed] (rule 4.12) and the list of timed topics, [timed], are
    defined in [NodeModel]: the direct input relations (rule 4.16),
    [read_paths] and the specifications ([DDC]) depend on them. *)

(** The globals of a timed topic's clock. *)
Definition clock_names (tp : topic) : list ident :=
  [time_var (tp_cname tp); new_var (tp_cname tp); rcvd_var (tp_cname tp)].

(** ** Names, for the well-formedness rules *)

Section NAMES.

Variable m : node_model.

(** The global names, in the order of [Generator.build_defs]
    ([Generatorproof.build_defs_names]). *)
Definition topic_extern_names (tp : topic) : list ident :=
  match tp_dir tp with
  | Subscribe => [subscribe_name (tp_cname tp)]
  | Publish => [advertise_name (tp_cname tp); publish_name (tp_cname tp)]
  end.

(** The time functions are declared only by a node that has timed
    topics (rule 4.12: [ros_now]) or stamps messages (rule 4.13: the
    other two), so the C of other nodes is unchanged. *)
Definition now_extern_names : list ident :=
  match timed m with [] => [] | _ :: _ => [ros_now_name] end.

Definition stamp_extern_names : list ident :=
  match nm_stamps m with [] => [] | _ :: _ => [ros_time_sec_name; ros_time_nsec_name] end.

Definition time_extern_names : list ident := now_extern_names ++ stamp_extern_names.

Definition global_names : list ident :=
  [ros_init_name; ros_ok_name; ros_spinOnce_name; ros_rate_sleep_name]
  ++ time_extern_names
  ++ flat_map topic_extern_names (nm_topics m)
  ++ [init_name m; step_name m; nm_in_var m; nm_out_var m]
  ++ map (fun tp => msg_var (tp_cname tp)) (subscribed m)
  ++ flat_map clock_names (timed m)
  ++ map (fun tp => callback_name (tp_cname tp)) (subscribed m)
  ++ [input_glue_name]
  ++ map (fun tp => output_glue_name (tp_cname tp)) (published m)
  ++ [loop_name; main_name].

(** The names of parameters, temporaries and local variables.  They are
    required distinct from the global names so that no local hides a
    global. *)
Definition local_names : list ident :=
  [msg_param; command_param; ok_temp; now_temp; age_temp]
  ++ map fst all_temps
  ++ map (fun tp => cmd_var (tp_cname tp)) (published m).

(** Struct names. *)
Definition struct_names : list ident :=
  map md_name (nm_msgs m) ++ [nm_in_struct m; nm_out_struct m].

(** Every name that reaches the C text. *)
Definition c_names : list ident :=
  global_names ++ local_names ++ struct_names
  ++ flat_map (fun md => map fst (md_fields md)) (nm_msgs m)
  ++ map fst (nm_inputs m) ++ map fst (nm_outputs m).

End NAMES.

(** ** Lexical rules *)

Definition char_between (lo hi : N) (c : ascii) : bool :=
  (lo <=? N_of_ascii c)%N && (N_of_ascii c <=? hi)%N.

Definition is_upper (c : ascii) : bool := char_between 65 90 c.
Definition is_lower (c : ascii) : bool := char_between 97 122 c.
Definition is_digit (c : ascii) : bool := char_between 48 57 c.
Definition is_letter (c : ascii) : bool := is_upper c || is_lower c.
Definition is_underscore (c : ascii) : bool := Ascii.eqb c "_"%char.

(** Every character satisfies [f]. *)
Fixpoint all_chars (f : ascii -> bool) (s : string) : bool :=
  match s with
  | EmptyString => true
  | String c s' => f c && all_chars f s'
  end.

(** Keywords of C11 and C++11 (the C API over ROS is compiled as C++ too),
    and the alternative operator spellings of C++. *)
Definition c_keywords : list string :=
  ["auto"; "break"; "case"; "char"; "const"; "continue"; "default"; "do";
   "double"; "else"; "enum"; "extern"; "float"; "for"; "goto"; "if";
   "inline"; "int"; "long"; "register"; "restrict"; "return"; "short";
   "signed"; "sizeof"; "static"; "struct"; "switch"; "typedef"; "union";
   "unsigned"; "void"; "volatile"; "while";
   "alignas"; "alignof"; "asm"; "bool"; "catch"; "char16_t"; "char32_t";
   "class"; "constexpr"; "const_cast"; "decltype"; "delete"; "dynamic_cast";
   "explicit"; "export"; "false"; "friend"; "mutable"; "namespace"; "new";
   "noexcept"; "nullptr"; "operator"; "private"; "protected"; "public";
   "reinterpret_cast"; "static_assert"; "static_cast"; "template"; "this";
   "thread_local"; "throw"; "true"; "try"; "typeid"; "typename"; "using";
   "virtual"; "wchar_t";
   "and"; "and_eq"; "bitand"; "bitor"; "compl"; "not"; "not_eq"; "or";
   "or_eq"; "xor"; "xor_eq"].

(** Keywords of Coq's term language (the node name names Coq definitions). *)
Definition coq_keywords : list string :=
  ["as"; "at"; "cofix"; "else"; "end"; "exists"; "exists2"; "fix"; "for";
   "forall"; "fun"; "if"; "IF"; "in"; "let"; "match"; "mod"; "return";
   "SProp"; "Prop"; "Set"; "Type"; "then"; "using"; "where"; "with"].

(** Reserved by the C standard: [__x] and [_X]. *)
Definition reserved_prefix (s : string) : bool :=
  match s with
  | String c1 (String c2 _) => is_underscore c1 && (is_underscore c2 || is_upper c2)
  | _ => false
  end.

(** A C identifier: [[A-Za-z_][A-Za-z0-9_]*], at most 63 characters (the
    significant length guaranteed by C99), not a keyword, not reserved. *)
Definition valid_ident (s : string) : bool :=
  match s with
  | EmptyString => false
  | String c s' =>
      (is_letter c || is_underscore c)
      && all_chars (fun c => is_letter c || is_digit c || is_underscore c) s'
  end
  && (String.length s <=? 63)%nat
  && negb (existsb (String.eqb s) c_keywords)
  && negb (reserved_prefix s).

(** A ROS graph name: a letter, [/] or [~], then letters, digits, [_], [/]. *)
Definition valid_ros_name (s : string) : bool :=
  match s with
  | EmptyString => false
  | String c s' =>
      (is_letter c || Ascii.eqb c "/"%char || Ascii.eqb c "~"%char)
      && all_chars (fun c => is_letter c || is_digit c || is_underscore c || Ascii.eqb c "/"%char) s'
  end.

(** A ROS message type name [pkg/Type]: letters, digits and [_], exactly
    one [/], both parts non-empty. *)
Fixpoint ros_type_rest (seen_slash : bool) (nonempty : bool) (s : string) : bool :=
  match s with
  | EmptyString => seen_slash && nonempty
  | String c s' =>
      if Ascii.eqb c "/"%char then negb seen_slash && nonempty && ros_type_rest true false s'
      else (is_letter c || is_digit c || is_underscore c) && ros_type_rest seen_slash true s'
  end.

Definition valid_ros_type (s : string) : bool := ros_type_rest false false s.

(** The C struct of a ROS message type: [pkg/Type] gives [pkg_Type] (the
    front end's naming of message structs). *)
Fixpoint ros_type_struct (s : string) : string :=
  match s with
  | EmptyString => EmptyString
  | String c s' => String (if Ascii.eqb c "/"%char then "_"%char else c) (ros_type_struct s')
  end.

(** ** Auxiliary checks *)

Definition null {A : Type} (l : list A) : bool :=
  match l with [] => true | _ :: _ => false end.

(** Keys for names, paths and published fields. *)
Definition enc_pstep (s : pstep) : list bool :=
  match s with
  | PField f => true :: enc_string f
  | PIndex i => false :: enc_Z i
  end.

Definition enc_path : path -> list bool := enc_list enc_pstep.

Definition enc_target : ident * path -> list bool := enc_pair enc_string enc_path.

(** No element occurs twice (in linear time, with a trie): for the long
    lists of a model (names, topics, relations). *)
Definition nodup_keys {A : Type} (enc : A -> list bool) (l : list A) : bool :=
  match find_dup enc l with None => true | Some _ => false end.

(** Fail naming the first repeated element. *)
Definition check_nodup_keys {A : Type} (enc : A -> list bool) (show : A -> errmsg) (l : list A) : res unit :=
  match find_dup enc l with None => OK tt | Some x => Error (show x) end.

(** The same by comparing every pair, for short lists (the fields of a
    message): the first element of [l] that occurs again later in [l]. *)
Fixpoint first_dup {A : Type} (eqb : A -> A -> bool) (l : list A) : option A :=
  match l with
  | [] => None
  | x :: l' => if existsb (eqb x) l' then Some x else first_dup eqb l'
  end.

Definition nodupb {A : Type} (eqb : A -> A -> bool) (l : list A) : bool :=
  match first_dup eqb l with None => true | Some _ => false end.

Definition check_nodup {A : Type} (eqb : A -> A -> bool) (show : A -> errmsg) (l : list A) : res unit :=
  match first_dup eqb l with None => OK tt | Some x => Error (show x) end.

(** Check every element, failing at the first bad one. *)
Fixpoint check_all {A : Type} (f : A -> res unit) (l : list A) : res unit :=
  match l with
  | [] => OK tt
  | x :: l' => do _ <- f x; check_all f l'
  end.

(** Decimal notation of an integer, for messages. *)
Fixpoint digits (fuel : nat) (n : Z) (acc : string) : string :=
  match fuel with
  | O => acc
  | S fuel' =>
      let acc' := String (ascii_of_nat (48 + Z.to_nat (n mod 10))) acc in
      if (n <? 10)%Z then acc' else digits fuel' (n / 10)%Z acc'
  end.

Definition string_of_Z (n : Z) : string :=
  if (n <? 0)%Z
  then ("-" ++ digits (S (Z.to_nat (Z.log2 (- n)))) (- n) "")%string
  else digits (S (Z.to_nat (Z.log2 n))) n "".

(** A path as written in the node model: [twist.linear.x], [covariance[35]]. *)
Fixpoint string_of_path (p : path) : string :=
  match p with
  | [] => ""
  | PField f :: p' => ("." ++ f ++ string_of_path p')%string
  | PIndex i :: p' => ("[" ++ string_of_Z i ++ "]" ++ string_of_path p')%string
  end.

(** ** Well-formedness rules (DESIGN.md, section 4) *)

(** Array sizes are positive and fit the [int] index constants. *)
Definition max_array : Z := 2147483647.

(** Rule: a field type refers only to messages in [seen] (the messages
    defined before), and its arrays have sizes in range. *)
Fixpoint ftype_ok (seen : list ident) (t : ftype) : bool :=
  match t with
  | FTprim _ => true
  | FTmsg id => existsb (ident_eqb id) seen
  | FTarray t' n => (0 <? n)%Z && (n <=? max_array)%Z && ftype_ok seen t'
  end.

(** Rule: a controller field is a primitive or a fixed-size array of a
    primitive (Embedded Coder's [real32_T Scan[1081]]). *)
Definition ctrl_ftype_ok (t : ftype) : bool :=
  match t with
  | FTprim _ => true
  | FTarray (FTprim _) n => (0 <? n)%Z && (n <=? max_array)%Z
  | _ => false
  end.

(** The primitive of the leaf [p] of a controller field of type [t]. *)
Definition ctrl_prim (t : ftype) (p : path) : option prim := resolve_prim [] t p.

(** Rule: a message has fields, distinct field names and good field types. *)
Definition msgdef_ok (seen : list ident) (md : msgdef) : bool :=
  negb (null (md_fields md))
  && nodupb ident_eqb (map fst (md_fields md))
  && forallb (fun ft => ftype_ok seen (snd ft)) (md_fields md).

(** Rule: every message only refers to the messages before it. *)
Fixpoint msgs_ok (seen : list ident) (msgs : list msgdef) : bool :=
  match msgs with
  | [] => true
  | md :: msgs' => msgdef_ok seen md && msgs_ok (md_name md :: seen) msgs'
  end.

(** Rule: a topic has a ROS name, a ROS message type [pkg/Type] whose
    struct is the topic's message struct, a queue, and a defined message
    type. *)
Definition topic_ok (msgs : list msgdef) (tp : topic) : bool :=
  valid_ros_name (tp_name tp)
  && valid_ros_type (tp_type tp)
  && String.eqb (tp_msg tp) (ros_type_struct (tp_type tp))
  && (1 <=? tp_queue tp)%nat
  && match find_msg msgs (tp_msg tp) with Some _ => true | None => false end.

(** Rule (the paper's [type_checking_input_glue], on model types): an input
    relation reads a leaf of a subscribed topic's message whose primitive
    type is the controller input's. *)
Definition inrel_ok (m : node_model) (tb : tables) (ir : inrel) : bool :=
  match lookup_topic tb (ir_topic ir) with
  | None => false
  | Some tp =>
      is_subscribed tp
      && match tget (enc_string (ir_input ir)) (tb_inputs tb) with
         | None => false
         | Some t =>
             match ctrl_prim t (ir_elem ir), resolve_prim (nm_msgs m) (FTmsg (tp_msg tp)) (ir_path ir) with
             | Some q, Some q' => prim_eqb q' q
             | _, _ => false
             end
         end
  end.

(** Rule: an output relation writes a leaf of a published topic's message
    whose primitive type is the controller output's leaf's. *)
Definition outrel_ok (m : node_model) (tb : tables) (o : outrel) : bool :=
  match tget (enc_string (or_output o)) (tb_outputs tb) with
  | None => false
  | Some t =>
      match ctrl_prim t (or_elem o) with
      | None => false
      | Some q =>
          match lookup_topic tb (or_topic o) with
          | None => false
          | Some tp =>
              is_published tp
              && match resolve_prim (nm_msgs m) (FTmsg (tp_msg tp)) (or_path o) with
                 | None => false
                 | Some q' => prim_eqb q' q
                 end
          end
      end
  end.

(** The leaves of controller inputs fed by an input relation or a
    derived input, in model order: the input and the path in it. *)
Definition fed_list (m : node_model) : list (ident * path) :=
  map (fun ir => (ir_input ir, ir_elem ir)) (nm_inrels m) ++ map (fun dr => (dr_input dr, [])) (nm_drels m).

Definition fed_inputs (m : node_model) : ptree unit :=
  tset_of_list enc_target (fed_list m).

(** Rule 4.13: a stamp is written in a published topic's message, at a
    field of the model's time message ([NodeModel.time_msg]: ROS 1's
    [ros_time] of two [uint32] fields [sec] and [nsec], or ROS 2's
    [builtin_interfaces_Time] of an [int32] [sec] and a [uint32]
    [nanosec]) that no output relation writes into. *)
Fixpoint path_prefixb (p q : path) : bool :=
  match p, q with
  | [], _ => true
  | s :: p', t :: q' => pstep_eqb s t && path_prefixb p' q'
  | _ :: _, [] => false
  end.

Definition ros_time_fields : list (ident * ftype) := [("sec", FTprim Puint32); ("nsec", FTprim Puint32)].

Definition time_msg_ok (msgs : list msgdef) : bool :=
  match find_msg msgs (time_msg msgs) with
  | Some md =>
      match md_fields md with
      | [(s, FTprim qs); (n, FTprim Puint32)] =>
          ident_eqb s "sec" && prim_eqb qs (time_sec_prim msgs) && ident_eqb n (time_nsec_field msgs)
      | _ => false
      end
  | None => false
  end.

Definition stamp_ok (m : node_model) (tb : tables) (st : ident * path) : bool :=
  match lookup_topic tb (fst st) with
  | None => false
  | Some tp =>
      is_published tp
      && match resolve (nm_msgs m) (FTmsg (tp_msg tp)) (snd st) with
         | Some (FTmsg id) => ident_eqb id (time_msg (nm_msgs m))
         | _ => false
         end
      && forallb (fun o => negb (ident_eqb (or_topic o) (fst st) && path_prefixb (snd st) (or_path o)))
                 (nm_outrels m)
  end.

(** Rule 4.13: a stamp copied from another topic: the published topic is
    stamped, the source is a subscribed topic, and the source path is a
    field of its message of the model's time message. *)
Definition stamp_from_ok (m : node_model) (tb : tables) (sf : ident * (ident * path)) : bool :=
  existsb (fun st => ident_eqb (fst st) (fst sf)) (nm_stamps m)
  && match lookup_topic tb (fst (snd sf)) with
     | Some tp =>
         is_subscribed tp
         && match resolve (nm_msgs m) (FTmsg (tp_msg tp)) (snd (snd sf)) with
            | Some (FTmsg id) => ident_eqb id (time_msg (nm_msgs m))
            | _ => false
            end
     | None => false
     end.

(** Rule 4.14: a carried string of at most [n] bytes is a message of the
    fields [len] ([uint32]), [truncated] ([bool]) and [data] ([uint8[n]]),
    [string_msg] gives its [n]. *)
Definition max_string : Z := 1048576.

Definition string_msg (msgs : list msgdef) (id : ident) : option Z :=
  match find_msg msgs id with
  | Some md =>
      match md_fields md with
      | [(l, FTprim Puint32); (t, FTprim Pbool); (d, FTarray (FTprim Puint8) n)] =>
          if ident_eqb l "len" && ident_eqb t "truncated" && ident_eqb d "data" && (n <=? max_string)%Z
          then Some n else None
      | _ => None
      end
  | None => None
  end.

(** Rule 4.14: a constant string is written in a published topic's
    message, at a string field of at least as many bytes as the constant
    has, each a byte, and no output relation of the topic writes into
    the string. *)
Definition is_byte (b : Z) : bool := (0 <=? b)%Z && (b <=? 255)%Z.

Definition string_ok (m : node_model) (tb : tables) (st : ident * (path * list Z)) : bool :=
  match lookup_topic tb (fst st) with
  | None => false
  | Some tp =>
      is_published tp
      && match resolve (nm_msgs m) (FTmsg (tp_msg tp)) (fst (snd st)) with
         | Some (FTmsg id) =>
             match string_msg (nm_msgs m) id with
             | Some n => (Z.of_nat (length (snd (snd st))) <=? n)%Z
             | None => false
             end
         | _ => false
         end
      && forallb is_byte (snd (snd st))
      && forallb (fun o => negb (ident_eqb (or_topic o) (fst st) && path_prefixb (fst (snd st)) (or_path o)))
                 (nm_outrels m)
  end.

(** The topic and path of a constant string. *)
Definition string_target (st : ident * (path * list Z)) : ident * path := (fst st, fst (snd st)).

(** Rule 4.12: a timeout is on a subscribed topic, from the period to a
    day (86,400,000 ms). *)
Definition max_timeout_ms : Z := 86400000.

Definition timeout_ok (m : node_model) (tb : tables) (ct : ident * Z) : bool :=
  match lookup_topic tb (fst ct) with
  | Some tp => is_subscribed tp && (nm_period_ms m <=? snd ct)%Z && (snd ct <=? max_timeout_ms)%Z
  | None => false
  end.

(** The timeout of the topic with C name [c], if it has one. *)
Definition timeout_of (m : node_model) (c : ident) : option Z := find_assoc c (nm_timeouts m).

(** Rule 4.12: a fallback value is a value of its controller input's
    type, and the input is fed by an input relation of a topic with a
    timeout. *)
Definition fallback_ok (m : node_model) (tb : tables) (xv : ident * val) : bool :=
  match tget (enc_string (fst xv)) (tb_inputs tb) with
  | Some (FTprim q) =>
      val_has_typeb (snd xv) (ctype_of_prim q)
      && existsb (fun ir => ident_eqb (ir_input ir) (fst xv)
                            && existsb (fun ct => ident_eqb (fst ct) (ir_topic ir)) (nm_timeouts m))
                 (nm_inrels m)
  | _ => false
  end.

(** The type of a derived input. *)
Definition derived_prim (k : derived) : prim :=
  match k with Dage_ms => Puint32 | Dis_new | Dreceived => Pbool end.

(** Rule 4.12: a derived input is about a subscribed topic and feeds a
    controller input of its type. *)
Definition drel_ok (m : node_model) (tb : tables) (dr : drel) : bool :=
  match lookup_topic tb (dr_topic dr) with
  | Some tp =>
      is_subscribed tp
      && match tget (enc_string (dr_input dr)) (tb_inputs tb) with
         | Some (FTprim q) => prim_eqb q (derived_prim (dr_kind dr))
         | _ => false
         end
  | None => false
  end.

(** The well-formedness of a node model, as a boolean. *)
Definition wf (m : node_model) : bool :=
  let tb := make_tables m in
  let fed := fed_inputs m in
  (0 <? nm_period_ms m)%Z
  && valid_ident (nm_name m) && negb (existsb (String.eqb (nm_name m)) coq_keywords)
  && valid_ident (nm_ctrl m)
  && nodup_keys enc_string (map tp_cname (nm_topics m))
  && nodup_keys enc_string (map tp_name (nm_topics m))
  && forallb valid_ident (c_names m)
  && nodup_keys enc_string (global_names m ++ local_names m)
  && nodup_keys enc_string (struct_names m)
  && msgs_ok [] (nm_msgs m)
  && negb (null (nm_inputs m)) && nodup_keys enc_string (map fst (nm_inputs m))
  && forallb (fun xt => ctrl_ftype_ok (snd xt)) (nm_inputs m)
  && negb (null (nm_outputs m)) && nodup_keys enc_string (map fst (nm_outputs m))
  && forallb (fun xt => ctrl_ftype_ok (snd xt)) (nm_outputs m)
  && forallb (topic_ok (nm_msgs m)) (nm_topics m)
  && forallb (inrel_ok m tb) (nm_inrels m)
  && forallb (timeout_ok m tb) (nm_timeouts m)
  && nodup_keys enc_string (map fst (nm_timeouts m))
  && forallb (drel_ok m tb) (nm_drels m)
  && nodup_keys enc_target (fed_list m)
  && forallb (fun l => tmem enc_target (fst l) fed) (ctrl_leaves (nm_inputs m))
  && forallb (fallback_ok m tb) (nm_fallbacks m)
  && nodup_keys enc_string (map fst (nm_fallbacks m))
  && forallb (outrel_ok m tb) (nm_outrels m)
  && (null (nm_stamps m) || time_msg_ok (nm_msgs m))
  && forallb (stamp_ok m tb) (nm_stamps m)
  && nodup_keys enc_string (map fst (nm_stamps m))
  && forallb (stamp_from_ok m tb) (nm_stamp_from m)
  && nodup_keys enc_string (map fst (nm_stamp_from m))
  && forallb (string_ok m tb) (nm_strings m)
  && nodup_keys enc_target (map string_target (nm_strings m))
  && nodup_keys enc_target (map (fun o => (or_topic o, or_path o)) (nm_outrels m)).

(** ** The same rules, failing with a message that names the culprit *)

Definition gen_error (s : string) (x : string) : errmsg := [MSG ("Generator: " ++ s)%string; CTX x].

Definition check_ident (what : string) (x : ident) : res unit :=
  assertion (valid_ident x) (gen_error (what ++ " is not a valid C identifier: ")%string x).

Fixpoint ftype_check (md : ident) (seen : list ident) (t : ftype) : res unit :=
  match t with
  | FTprim _ => OK tt
  | FTmsg id =>
      assertion (existsb (ident_eqb id) seen)
        [MSG "Generator: message "; CTX md; MSG " refers to message "; CTX id;
         MSG ", which is not defined before it"]
  | FTarray t' n =>
      do _ <- assertion ((0 <? n)%Z && (n <=? max_array)%Z)
                [MSG "Generator: array size out of range in message "; CTX md;
                 MSG ": "; MSG (string_of_Z n)];
      ftype_check md seen t'
  end.

Definition msgdef_check (seen : list ident) (md : msgdef) : res unit :=
  do _ <- assertion (negb (null (md_fields md)))
            (gen_error "message has no carried field: " (md_name md));
  do _ <- check_nodup ident_eqb
            (fun f => [MSG "Generator: field "; CTX f; MSG " defined twice in message "; CTX (md_name md)])
            (map fst (md_fields md));
  check_all (fun ft => ftype_check (md_name md) seen (snd ft)) (md_fields md).

Fixpoint msgs_check (seen : list ident) (msgs : list msgdef) : res unit :=
  match msgs with
  | [] => OK tt
  | md :: msgs' => do _ <- msgdef_check seen md; msgs_check (md_name md :: seen) msgs'
  end.

Definition topic_check (msgs : list msgdef) (tp : topic) : res unit :=
  do _ <- assertion (valid_ros_name (tp_name tp)) (gen_error "not a valid ROS graph name: " (tp_name tp));
  do _ <- assertion (valid_ros_type (tp_type tp))
            [MSG "Generator: not a ROS message type of the form package/Type: "; CTX (tp_type tp);
             MSG " (topic "; CTX (tp_name tp); MSG ")"];
  do _ <- assertion (String.eqb (tp_msg tp) (ros_type_struct (tp_type tp)))
            [MSG "Generator: the message struct "; CTX (tp_msg tp); MSG " of topic "; CTX (tp_name tp);
             MSG " is not the struct of its type "; CTX (tp_type tp)];
  do _ <- assertion (1 <=? tp_queue tp)%nat (gen_error "queue size must be at least 1 for topic " (tp_name tp));
  match find_msg msgs (tp_msg tp) with
  | Some _ => OK tt
  | None => Error [MSG "Generator: unknown message type "; CTX (tp_msg tp);
                   MSG " of topic "; CTX (tp_name tp)]
  end.

Definition inrel_check (m : node_model) (tb : tables) (ir : inrel) : res unit :=
  match lookup_topic tb (ir_topic ir) with
  | None => Error (gen_error "input relation for unknown topic " (ir_topic ir))
  | Some tp =>
      do _ <- assertion (is_subscribed tp)
                [MSG "Generator: input relation reads topic "; CTX (ir_topic ir);
                 MSG ", which is not subscribed"];
      match tget (enc_string (ir_input ir)) (tb_inputs tb) with
      | None => Error (gen_error "input relation for unknown controller input " (ir_input ir))
      | Some t =>
          match ctrl_prim t (ir_elem ir) with
          | None =>
              Error [MSG "Generator: input relation: "; CTX (ir_input ir ++ string_of_path (ir_elem ir))%string;
                     MSG " is not a scalar leaf of the controller's inputs"]
          | Some q =>
          match resolve_prim (nm_msgs m) (FTmsg (tp_msg tp)) (ir_path ir) with
          | None =>
              Error [MSG "Generator: input relation: "; CTX (string_of_path (ir_path ir));
                     MSG " is not a carried scalar field of message "; CTX (tp_msg tp)]
          | Some q' =>
              assertion (prim_eqb q' q)
                [MSG "Generator: type mismatch in input relation: ";
                 CTX (ir_topic ir ++ string_of_path (ir_path ir))%string;
                 MSG (" is " ++ prim_name q' ++ " but controller input ")%string;
                 CTX (ir_input ir ++ string_of_path (ir_elem ir))%string; MSG (" is " ++ prim_name q)%string]
          end
          end
      end
  end.

Definition outrel_check (m : node_model) (tb : tables) (o : outrel) : res unit :=
  match tget (enc_string (or_output o)) (tb_outputs tb) with
  | None => Error (gen_error "output relation from unknown controller output " (or_output o))
  | Some t =>
      match ctrl_prim t (or_elem o) with
      | None =>
          Error [MSG "Generator: output relation: "; CTX (or_output o ++ string_of_path (or_elem o))%string;
                 MSG " is not a scalar leaf of the controller's outputs"]
      | Some q =>
      match lookup_topic tb (or_topic o) with
      | None => Error (gen_error "output relation for unknown topic " (or_topic o))
      | Some tp =>
          do _ <- assertion (is_published tp)
                    [MSG "Generator: output relation writes topic "; CTX (or_topic o);
                     MSG ", which is not published"];
          match resolve_prim (nm_msgs m) (FTmsg (tp_msg tp)) (or_path o) with
          | None =>
              Error [MSG "Generator: output relation: "; CTX (string_of_path (or_path o));
                     MSG " is not a carried scalar field of message "; CTX (tp_msg tp)]
          | Some q' =>
              assertion (prim_eqb q' q)
                [MSG "Generator: type mismatch in output relation: controller output ";
                 CTX (or_output o ++ string_of_path (or_elem o))%string; MSG (" is " ++ prim_name q ++ " but ")%string;
                 CTX (or_topic o ++ string_of_path (or_path o))%string;
                 MSG (" is " ++ prim_name q')%string]
          end
      end
      end
  end.

(** [wf_check m = OK tt] iff [wf m = true] ([Generatorproof.wf_check_wf]). *)
Definition wf_check (m : node_model) : res unit :=
  let tb := make_tables m in
  let fed := fed_inputs m in
  do _ <- assertion (0 <? nm_period_ms m)%Z [MSG "Generator: period_ms must be positive"];
  do _ <- check_ident "node name" (nm_name m);
  do _ <- assertion (negb (existsb (String.eqb (nm_name m)) coq_keywords))
            (gen_error "the node name is a Coq keyword: " (nm_name m));
  do _ <- check_ident "controller name" (nm_ctrl m);
  do _ <- check_nodup_keys enc_string (gen_error "two topics with the C name ") (map tp_cname (nm_topics m));
  do _ <- check_nodup_keys enc_string (gen_error "topic declared twice: ") (map tp_name (nm_topics m));
  do _ <- check_all (check_ident "name") (c_names m);
  do _ <- check_nodup_keys enc_string (gen_error "name defined twice: ") (global_names m ++ local_names m);
  do _ <- check_nodup_keys enc_string (gen_error "struct defined twice: ") (struct_names m);
  do _ <- msgs_check [] (nm_msgs m);
  do _ <- assertion (negb (null (nm_inputs m))) (gen_error "controller has no input: " (nm_ctrl m));
  do _ <- check_nodup_keys enc_string (gen_error "controller input declared twice: ") (map fst (nm_inputs m));
  do _ <- check_all (fun xt => assertion (ctrl_ftype_ok (snd xt))
                                 (gen_error "controller input is neither a primitive nor an array of a primitive: " (fst xt)))
            (nm_inputs m);
  do _ <- assertion (negb (null (nm_outputs m))) (gen_error "controller has no output: " (nm_ctrl m));
  do _ <- check_nodup_keys enc_string (gen_error "controller output declared twice: ") (map fst (nm_outputs m));
  do _ <- check_all (fun xt => assertion (ctrl_ftype_ok (snd xt))
                                 (gen_error "controller output is neither a primitive nor an array of a primitive: " (fst xt)))
            (nm_outputs m);
  do _ <- check_all (topic_check (nm_msgs m)) (nm_topics m);
  do _ <- check_all (inrel_check m tb) (nm_inrels m);
  do _ <- check_all (fun ct => assertion (timeout_ok m tb ct)
                                 [MSG "Generator: bad timeout (rule 4.12) on topic "; CTX (fst ct);
                                  MSG ": "; MSG (string_of_Z (snd ct));
                                  MSG " ms must be on a subscribed topic, from the period to 86400000 ms"])
            (nm_timeouts m);
  do _ <- check_nodup_keys enc_string (gen_error "timeout given twice for topic ") (map fst (nm_timeouts m));
  do _ <- check_all (fun dr => assertion (drel_ok m tb dr)
                                 [MSG "Generator: bad derived input (rule 4.12) "; CTX (dr_input dr);
                                  MSG ": it must be of topic "; CTX (dr_topic dr);
                                  MSG ", subscribed, and feed a controller input of its type (bool, or uint32 for age_ms)"])
            (nm_drels m);
  do _ <- check_nodup_keys enc_target
            (fun xp => gen_error "controller input fed by several input relations: " (fst xp ++ string_of_path (snd xp))%string)
            (fed_list m);
  do _ <- check_all (fun l => assertion (tmem enc_target (fst l) fed)
                                 (gen_error "controller input not fed by any input relation: " (fst (fst l) ++ string_of_path (snd (fst l)))%string))
            (ctrl_leaves (nm_inputs m));
  do _ <- check_all (fun xv => assertion (fallback_ok m tb xv)
                                 [MSG "Generator: bad fallback (rule 4.12) for controller input "; CTX (fst xv);
                                  MSG ": it must be a value of the input's type, for an input fed by a topic with a timeout"])
            (nm_fallbacks m);
  do _ <- check_nodup_keys enc_string (gen_error "fallback given twice for controller input ") (map fst (nm_fallbacks m));
  do _ <- check_all (outrel_check m tb) (nm_outrels m);
  do _ <- assertion (null (nm_stamps m) || time_msg_ok (nm_msgs m))
            [MSG "Generator: stamps need the message ros_time with the uint32 fields sec and nsec (ROS 2: builtin_interfaces_Time with the int32 sec and the uint32 nanosec)"];
  do _ <- check_all (fun st => assertion (stamp_ok m tb st)
                                 [MSG "Generator: bad stamp (rule 4.13) on topic "; CTX (fst st);
                                  MSG ": "; CTX (string_of_path (snd st));
                                  MSG " must be a time field of a published message that no output relation writes"])
            (nm_stamps m);
  do _ <- check_nodup_keys enc_string (gen_error "topic stamped twice: ") (map fst (nm_stamps m));
  do _ <- check_all (fun sf => assertion (stamp_from_ok m tb sf)
                                 [MSG "Generator: bad stamp source (rule 4.13) for topic "; CTX (fst sf);
                                  MSG ": "; CTX (fst (snd sf) ++ string_of_path (snd (snd sf)))%string;
                                  MSG " must be a time field of a subscribed topic's message, for a stamped topic"])
            (nm_stamp_from m);
  do _ <- check_nodup_keys enc_string (gen_error "stamp source given twice for topic ") (map fst (nm_stamp_from m));
  do _ <- check_all (fun st => assertion (string_ok m tb st)
                                 [MSG "Generator: bad constant string (rule 4.14) on topic "; CTX (fst st);
                                  MSG ": "; CTX (string_of_path (fst (snd st)));
                                  MSG " must be a string field of a published message, long enough, that no output relation writes, and the constant bytes"])
            (nm_strings m);
  do _ <- check_nodup_keys enc_target
            (fun tp => gen_error "constant string given twice: " (fst tp ++ string_of_path (snd tp))%string)
            (map string_target (nm_strings m));
  check_nodup_keys enc_target
    (fun tp => gen_error "published field fed twice: " (fst tp ++ string_of_path (snd tp))%string)
    (map (fun o => (or_topic o, or_path o)) (nm_outrels m)).

