(** * The node model *)

(** A ROS node as described by the user (DESIGN.md, section 4), after the
    Python front end has resolved message types: the node's period, its
    topics, the C interface of the controller it runs, the definitions of the
    messages it carries, and the relations saying which message field feeds
    which controller field and back.  The front end emits exactly these terms
    into the per-node Coq file; [Generator.generate] turns them into a
    program of [Syntax]. *)

From Coq Require Import String List ZArith Bool.
From ROSGen Require Import Syntax Values.
Import ListNotations.

Local Open Scope string_scope.

(** ** ROS primitive types *)

(** The ROS primitive types that the glue carries.  [Pbool] and [Puint8]
    have the same C type but are different model types: a relation joins two
    fields of the same model type, so [bool] to [uint8] is refused. *)
Inductive prim : Type :=
  | Pbool | Pint8 | Puint8 | Pint16 | Puint16 | Pint32 | Puint32
  | Pint64 | Puint64 | Pfloat32 | Pfloat64.

Definition prim_eq (a b : prim) : {a = b} + {a <> b}.
Proof. decide equality. Defined.

Definition prim_eqb (a b : prim) : bool := if prim_eq a b then true else false.

Lemma prim_eqb_true: forall a b, prim_eqb a b = true <-> a = b.
Proof. intros a b; unfold prim_eqb; destruct (prim_eq a b); split; congruence. Qed.

(** The C type of a primitive (Simulink's name in brackets):
    [bool] is [unsigned char] ([boolean_T]), [float64] is [double]
    ([real_T]), and so on. *)
Definition ctype_of_prim (q : prim) : type :=
  match q with
  | Pbool => Tint I8 Unsigned
  | Pint8 => Tint I8 Signed
  | Puint8 => Tint I8 Unsigned
  | Pint16 => Tint I16 Signed
  | Puint16 => Tint I16 Unsigned
  | Pint32 => Tint I32 Signed
  | Puint32 => Tint I32 Unsigned
  | Pint64 => Tlong Signed
  | Puint64 => Tlong Unsigned
  | Pfloat32 => Tfloat F32
  | Pfloat64 => Tfloat F64
  end.

(** The ROS name of a primitive, for error messages. *)
Definition prim_name (q : prim) : string :=
  match q with
  | Pbool => "bool" | Pint8 => "int8" | Puint8 => "uint8"
  | Pint16 => "int16" | Puint16 => "uint16" | Pint32 => "int32"
  | Puint32 => "uint32" | Pint64 => "int64" | Puint64 => "uint64"
  | Pfloat32 => "float32" | Pfloat64 => "float64"
  end.

(** ** Message definitions *)

(** The type of a carried message field: a primitive, a nested message
    (named by its [md_name]), or a fixed-size array.  Strings and
    variable-length arrays are not carried: the front end drops them. *)
Inductive ftype : Type :=
  | FTprim (q : prim)                (**r a primitive *)
  | FTmsg (m : ident)                (**r a nested message *)
  | FTarray (t : ftype) (n : Z).     (**r [t[n]] *)

(** A message definition, the single source of truth for the C [struct]
    of a message.  [md_name] is the C struct name, e.g.
    ["geometry_msgs_TwistStamped"]; fields are in declaration order.
    ROS [time] and [duration] are ordinary message definitions named
    ["ros_time"] and ["ros_duration"]. *)
Record msgdef : Type := mkmsgdef {
  md_name : ident;
  md_fields : list (ident * ftype)
}.

(** The C type of a field type. *)
Fixpoint ctype_of_ftype (t : ftype) : type :=
  match t with
  | FTprim q => ctype_of_prim q
  | FTmsg m => Tstruct m
  | FTarray t' n => Tarray (ctype_of_ftype t') n
  end.

(** The C struct of a message definition. *)
Definition composite_of_msgdef (md : msgdef) : composite_definition :=
  Composite (md_name md) (map (fun ft => (fst ft, ctype_of_ftype (snd ft))) (md_fields md)).

(** ** Topics *)

Inductive direction : Type := Subscribe | Publish.

Definition direction_eqb (a b : direction) : bool :=
  match a, b with
  | Subscribe, Subscribe | Publish, Publish => true
  | _, _ => false
  end.

(** A topic: [tp_name] is the ROS graph name (used only by the environment
    model and the C++ wrapper), [tp_cname] the C-safe base name from which
    the generated C names are derived (e.g. ["landshark_left_wheel_velocity"]),
    [tp_type] the ROS type name of its messages, [pkg/Type] (e.g.
    ["geometry_msgs/TwistStamped"]: what the C++ wrapper subscribes or
    advertises with; the generated C never sees it), [tp_msg] the [md_name]
    of its message type (the C struct, ["geometry_msgs_TwistStamped"]:
    [Wellformed.topic_ok] requires it to be [ros_type_struct tp_type]), and
    [tp_queue] the queue size of its subscription or advertisement. *)
Record topic : Type := mktopic {
  tp_name : string;
  tp_cname : ident;
  tp_type : string;
  tp_dir : direction;
  tp_msg : ident;
  tp_queue : nat
}.

(** ** Paths and relations *)

(** A path into a message: field selections and constant array indices,
    e.g. [twist.linear.x] or [pose.covariance[35]]. *)
Inductive pstep : Type :=
  | PField (f : ident)     (**r [.f] *)
  | PIndex (i : Z).        (**r [[i]] *)

Definition path := list pstep.

(** An input relation (an SI row of the paper's Table 1): the leaf
    [ir_path] of the last message received on topic [ir_topic] (a
    [tp_cname]) feeds the leaf [ir_elem] of the controller input field
    [ir_input]: the field itself ([[]]) for a scalar input, one element
    ([[PIndex i]]) of an array input (Embedded Coder's [real32_T
    Scan[1081]]). *)
Record inrel : Type := mkinrel_at {
  ir_topic : ident;
  ir_path : path;
  ir_input : ident;
  ir_elem : path
}.

(** An input relation into a scalar input. *)
Definition mkinrel (t : ident) (p : path) (x : ident) : inrel := mkinrel_at t p x [].

(** An output relation (a PO row): the leaf [or_elem] of the controller
    output field [or_output] (the field itself, or one element of an
    array output) feeds the leaf [or_path] of the message published on
    [or_topic]. *)
Record outrel : Type := mkoutrel_at {
  or_output : ident;
  or_elem : path;
  or_topic : ident;
  or_path : path
}.

(** An output relation from a scalar output. *)
Definition mkoutrel (y : ident) (t : ident) (p : path) : outrel := mkoutrel_at y [] t p.

(** ** Freshness *)

(** A derived input (rule 4.12): a controller input computed from when
    messages arrived on a subscribed topic rather than from their
    contents.  [Dis_new]: whether a message arrived on the topic since the
    previous cycle ([bool]); [Dreceived]: whether one ever arrived
    ([bool]); [Dage_ms]: the age in milliseconds of the newest one, at the
    cycle's time, saturating at [2^32 - 1], also when none arrived
    ([uint32]). *)
Inductive derived : Type := Dis_new | Dreceived | Dage_ms.

(** A derived relation: the derived input [dr_kind] of the topic whose
    C name is [dr_topic] feeds the controller input field [dr_input]. *)
Record drel : Type := mkdrel {
  dr_topic : ident;
  dr_kind : derived;
  dr_input : ident
}.

(** ** Node models *)

(** [nm_name] is the node's name, [nm_period_ms] its period.  The
    controller is a Simulink-style C unit named [nm_ctrl] ([Controller]),
    with functions [Controller_initialize] and [Controller_step]; its inputs
    are the global [nm_in_var] ([Controller_U]) of type [struct nm_in_struct]
    ([ExtU_Controller_T]) with fields [nm_inputs] in C order, and likewise
    for the outputs.  A controller field is a primitive or a fixed-size
    array of a primitive ([Wellformed.ctrl_ftype_ok]).  [nm_msgs] lists the message definitions in dependency
    order (a message only refers to messages defined before it).

    Freshness (rule 4.12): [nm_timeouts] gives some subscribed topics (by
    C name) a timeout in milliseconds; a message older than that at the
    cycle's time is stale.  [nm_fallbacks] gives some controller inputs
    fed by an input relation of such a topic the value they take while
    the topic is stale (the others keep the newest message's field:
    "hold").  [nm_drels] are the derived relations; they feed controller
    inputs like input relations do, and are not in [nm_inrels].

    Stamps (rule 4.13): [nm_stamps] names published topics (by C name)
    whose messages carry a stamp in the field of type [time] at the given
    path (the topic's [header.stamp]): the cycle's ROS time, or, for a
    topic that [nm_stamp_from] maps to a subscribed topic (by C name) and
    a [time] field of its message, that field of the newest message
    received on it.

    Constant strings (rule 4.14): [nm_strings] lists, for published
    topics (by C name), the path of a [string] field of the topic's
    message and the bytes of the constant it always holds.  A carried
    string of at most [N] bytes is a nested message of three fields,
    [len] ([uint32]), [truncated] ([bool]) and [data] ([uint8[N]])
    ([Wellformed.string_msg]). *)
Record node_model : Type := mknode_model {
  nm_name : ident;
  nm_period_ms : Z;
  nm_ctrl : ident;
  nm_in_var : ident;
  nm_in_struct : ident;
  nm_inputs : list (ident * ftype);
  nm_out_var : ident;
  nm_out_struct : ident;
  nm_outputs : list (ident * ftype);
  nm_msgs : list msgdef;
  nm_topics : list topic;
  nm_inrels : list inrel;
  nm_outrels : list outrel;
  nm_timeouts : list (ident * Z);
  nm_fallbacks : list (ident * val);
  nm_drels : list drel;
  nm_stamps : list (ident * path);
  nm_stamp_from : list (ident * (ident * path));
  nm_strings : list (ident * (path * list Z))
}.

(** ** Lookups *)

Definition ident_eqb (a b : ident) : bool := String.eqb a b.

Lemma ident_eqb_true: forall a b, ident_eqb a b = true <-> a = b.
Proof. intros; apply String.eqb_eq. Qed.

Lemma ident_eqb_refl: forall a, ident_eqb a a = true.
Proof. intros; apply ident_eqb_true; reflexivity. Qed.

Lemma ident_eqb_false: forall a b, ident_eqb a b = false <-> a <> b.
Proof.
  intros a b; rewrite <- ident_eqb_true; destruct (ident_eqb a b); intuition congruence.
Qed.

(** The definition of message [id]. *)
Definition find_msg (msgs : list msgdef) (id : ident) : option msgdef :=
  find (fun md => ident_eqb (md_name md) id) msgs.

(** Rule 4.13: the time message of the model's stamps.  ROS 1's [time]
    is the message ["ros_time"] ([uint32 sec], [uint32 nsec]); ROS 2's
    [builtin_interfaces/Time] is the message ["builtin_interfaces_Time"]
    ([int32 sec], [uint32 nanosec]).  A model defines ["ros_time"] only
    for the target ROS 1 (the ROS 2 reading has no built-in [time]): its
    stamps are ROS 1's if it does, ROS 2's otherwise. *)
Definition ros2_time_msg : ident := "builtin_interfaces_Time".
Definition time_is_ros2 (msgs : list msgdef) : bool :=
  match find_msg msgs "ros_time" with Some _ => false | None => true end.
Definition time_msg (msgs : list msgdef) : ident :=
  if time_is_ros2 msgs then ros2_time_msg else "ros_time".
(** The time's field of nanoseconds ([nsec], ROS 2's [nanosec]) and the
    type of its seconds ([uint32], ROS 2's [int32]). *)
Definition time_nsec_field (msgs : list msgdef) : ident :=
  if time_is_ros2 msgs then "nanosec" else "nsec".
Definition time_sec_prim (msgs : list msgdef) : prim :=
  if time_is_ros2 msgs then Pint32 else Puint32.

(** The topic whose C name is [c]. *)
Definition find_topic (tps : list topic) (c : ident) : option topic :=
  find (fun tp => ident_eqb (tp_cname tp) c) tps.

(** The subscribed and the published topics, in model order. *)
Definition is_subscribed (tp : topic) : bool := direction_eqb (tp_dir tp) Subscribe.
Definition is_published (tp : topic) : bool := direction_eqb (tp_dir tp) Publish.

Definition subscribed (m : node_model) : list topic := filter is_subscribed (nm_topics m).
Definition published (m : node_model) : list topic := filter is_published (nm_topics m).

(** ** Resolving paths *)

(** [resolve msgs t p] is the field type reached by following [p] from a
    value of field type [t], if every field exists and every index is in
    range. *)
Fixpoint resolve (msgs : list msgdef) (t : ftype) (p : path) : option ftype :=
  match p with
  | [] => Some t
  | PField f :: p' =>
      match t with
      | FTmsg id =>
          match find_msg msgs id with
          | Some md =>
              match find_assoc f (md_fields md) with
              | Some t' => resolve msgs t' p'
              | None => None
              end
          | None => None
          end
      | _ => None
      end
  | PIndex i :: p' =>
      match t with
      | FTarray t' n => if (0 <=? i)%Z && (i <? n)%Z then resolve msgs t' p' else None
      | _ => None
      end
  end.

(** The primitive at the end of a path that resolves to a scalar leaf. *)
Definition resolve_prim (msgs : list msgdef) (t : ftype) (p : path) : option prim :=
  match resolve msgs t p with
  | Some (FTprim q) => Some q
  | _ => None
  end.

(** ** Scalar leaves *)

(** The scalar leaves of a message are the paths to its primitive fields,
    through nested messages and every element of every array, in
    definition order, each with its primitive type.  They are computed by
    structural recursion on the list of message definitions in reverse
    dependency order ([scope]): a message refers only to messages after it
    in [scope]. *)

(** [0; 1; ...; n-1]. *)
Definition zrange (n : Z) : list Z := map Z.of_nat (seq 0 (Z.to_nat n)).

(** Put a step in front of every path. *)
Definition prefix_leaves (s : pstep) (l : list (path * prim)) : list (path * prim) :=
  map (fun pq => (s :: fst pq, snd pq)) l.

(** Leaves of a field type, given the leaves [ml] of each message. *)
Fixpoint ftype_leaves (ml : ident -> list (path * prim)) (t : ftype) : list (path * prim) :=
  match t with
  | FTprim q => [([], q)]
  | FTmsg id => ml id
  | FTarray t' n => flat_map (fun i => prefix_leaves (PIndex i) (ftype_leaves ml t')) (zrange n)
  end.

(** Leaves of a list of fields. *)
Definition fields_leaves (ml : ident -> list (path * prim))
                         (fs : list (ident * ftype)) : list (path * prim) :=
  flat_map (fun ft => prefix_leaves (PField (fst ft)) (ftype_leaves ml (snd ft))) fs.

(** Leaves of message [id] in [scope] (latest definition first). *)
Fixpoint scope_leaves (scope : list msgdef) (id : ident) : list (path * prim) :=
  match scope with
  | [] => []
  | md :: rest =>
      if ident_eqb (md_name md) id
      then fields_leaves (scope_leaves rest) (md_fields md)
      else scope_leaves rest id
  end.

(** Leaves of message [id] of the model's message list. *)
Definition leaves (msgs : list msgdef) (id : ident) : list (path * prim) :=
  scope_leaves (rev msgs) id.

(** ** What the node reads of a subscribed topic *)

(** Equality of paths. *)
Definition pstep_eqb (a b : pstep) : bool :=
  match a, b with
  | PField f, PField g => ident_eqb f g
  | PIndex i, PIndex j => Z.eqb i j
  | _, _ => false
  end.

Fixpoint path_eqb (p q : path) : bool :=
  match p, q with
  | [], [] => true
  | s :: p', t :: q' => pstep_eqb s t && path_eqb p' q'
  | _, _ => false
  end.

Lemma pstep_eqb_iff: forall a b, pstep_eqb a b = true <-> a = b.
Proof.
  intros [f|i] [g|j]; simpl; split; intros H; try discriminate; try congruence.
  - apply ident_eqb_true in H; subst; auto.
  - inversion H; apply ident_eqb_refl.
  - apply Z.eqb_eq in H; subst; auto.
  - inversion H; apply Z.eqb_refl.
Qed.

Lemma path_eqb_iff: forall p q, path_eqb p q = true <-> p = q.
Proof.
  induction p as [|s p IH]; intros [|t q]; simpl; split; intros H; try discriminate; auto.
  - apply andb_true_iff in H as [H1 H2]. apply pstep_eqb_iff in H1. apply IH in H2. congruence.
  - inversion H; subst. apply andb_true_iff; split; [apply pstep_eqb_iff|apply IH]; auto.
Qed.

(** The paths that the node reads in the messages of the subscribed
    topic with C name [c]: those that its input relations name, and the
    [sec] and [nsec] of a stamp copied from [c] (rule 4.13).  The
    topic's callback copies these leaves of a message, and only these. *)
(** A subscribed topic is timed (rule 4.12) when it has a timeout or a
    derived input: the glue keeps its clock. *)
Definition is_timed (m : node_model) (c : ident) : bool :=
  existsb (fun ct => ident_eqb (fst ct) c) (nm_timeouts m)
  || existsb (fun dr => ident_eqb (dr_topic dr) c) (nm_drels m).

(** The timed topics, in model order (the glue keeps a clock for each). *)
Definition timed (m : node_model) : list topic :=
  filter (fun tp => is_timed m (tp_cname tp)) (subscribed m).

(** ** The C structs of a model *)

(** These are the model's types, which the generated program declares and
    the specifications ([DDC]) speak of: they are defined here, with the
    model, not in the generator. *)

(** The struct of the controller's inputs or outputs. *)
Definition controller_composite (id : ident) (fs : list (ident * ftype)) : composite_definition :=
  Composite id (map (fun xt => (fst xt, ctype_of_ftype (snd xt))) fs).

(** All structs: the messages in dependency order, then the controller's. *)
Definition composites (m : node_model) : list composite_definition :=
  map composite_of_msgdef (nm_msgs m)
  ++ [controller_composite (nm_in_struct m) (nm_inputs m);
      controller_composite (nm_out_struct m) (nm_outputs m)].

(** ** Direct input relations (rule 4.16) *)

(** Whether a path goes through an array element ([ranges.data[5]]). *)
Definition has_index (p : path) : bool :=
  existsb (fun s => match s with PIndex _ => true | PField _ => false end) p.

(** An input relation is direct when its message leaf is an array
    element and its topic is not timed: the topic's callback then writes
    the leaf straight into [Controller_U], and [input_glue] does not copy
    it (one copy of a 1,081-element scan instead of two).  Any other
    input relation goes through the topic's global [c_msg] and
    [input_glue], as in the paper's Figures 10 and 12. *)
Definition is_direct (m : node_model) (ir : inrel) : bool :=
  has_index (ir_path ir) && negb (is_timed m (ir_topic ir)).

(** The input relations that [input_glue] copies, in model order. *)
Definition glue_inrels (m : node_model) : list inrel :=
  filter (fun ir => negb (is_direct m ir)) (nm_inrels m).

(** The direct input relations of the topic with C name [c], in model
    order: what its callback writes into [Controller_U]. *)
Definition direct_of (m : node_model) (c : ident) : list inrel :=
  filter (fun ir => ident_eqb (ir_topic ir) c && is_direct m ir) (nm_inrels m).

(** The leaves of the messages of the topic with C name [c] that the
    glue keeps in the topic's global [c_msg]: those of its input
    relations that are not direct, and the [sec] and [nsec] ([nanosec]
    on ROS 2) of a stamp copied from it (rule 4.13). *)
Definition read_paths (m : node_model) (c : ident) : list path :=
  (map ir_path (filter (fun ir => ident_eqb (ir_topic ir) c) (glue_inrels m))
  ++ flat_map (fun sf => if ident_eqb (fst (snd sf)) c
                         then [(snd (snd sf) ++ [PField "sec"])%list;
                               (snd (snd sf) ++ [PField (time_nsec_field (nm_msgs m))])%list]
                         else []) (nm_stamp_from m))%list.

Definition is_read (m : node_model) (c : ident) (lp : path) : bool :=
  existsb (path_eqb lp) (read_paths m c).

Lemma is_read_In: forall m c lp, is_read m c lp = true <-> In lp (read_paths m c).
Proof.
  intros m c lp. unfold is_read. rewrite existsb_exists. split.
  - intros (q & Hq & E). apply path_eqb_iff in E. subst; auto.
  - intros H. exists lp; split; auto. apply path_eqb_iff; auto.
Qed.

Lemma inrel_read: forall m ir, In ir (glue_inrels m) -> In (ir_path ir) (read_paths m (ir_topic ir)).
Proof.
  intros m ir H. unfold read_paths. apply in_or_app; left. apply in_map.
  apply filter_In; split; auto. apply ident_eqb_refl.
Qed.

Lemma glue_inrels_In:
  forall m ir, In ir (glue_inrels m) <-> In ir (nm_inrels m) /\ is_direct m ir = false.
Proof.
  intros m ir. unfold glue_inrels. rewrite filter_In, negb_true_iff. tauto.
Qed.

Lemma direct_of_In:
  forall m c ir, In ir (direct_of m c) <-> In ir (nm_inrels m) /\ ir_topic ir = c /\ is_direct m ir = true.
Proof.
  intros m c ir. unfold direct_of. rewrite filter_In, andb_true_iff.
  split; intros (A & B & C); repeat split; auto.
  - apply ident_eqb_true; auto.
  - subst c. apply ident_eqb_refl.
Qed.

Lemma incl_glue_inrels: forall m, incl (glue_inrels m) (nm_inrels m).
Proof. intros m ir H. apply glue_inrels_In in H. tauto. Qed.

Lemma stamp_from_read:
  forall m t s sp, In (t, (s, sp)) (nm_stamp_from m) ->
  In (sp ++ [PField "sec"])%list (read_paths m s)
  /\ In (sp ++ [PField (time_nsec_field (nm_msgs m))])%list (read_paths m s).
Proof.
  intros m t s sp H. unfold read_paths. split; apply in_or_app; right; apply in_flat_map;
    exists (t, (s, sp)); split; auto; simpl; rewrite ident_eqb_refl; simpl; auto.
Qed.

(** ** Controller fields *)

(** The scalar leaves of controller fields: each scalar field itself,
    each element of an array field, with its primitive. *)
Definition ctrl_leaves (fs : list (ident * ftype)) : list (ident * path * prim) :=
  flat_map (fun xt => map (fun lq => (fst xt, fst lq, snd lq)) (ftype_leaves (fun _ => []) (snd xt))) fs.

(** Scalar controller fields, as the diagram language has them. *)
Definition prim_fields (fs : list (ident * prim)) : list (ident * ftype) :=
  map (fun xq => (fst xq, FTprim (snd xq))) fs.
