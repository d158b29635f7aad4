(** * The glue-code generator *)

(** [generate m] turns a node model into a program of the Clight subset of
    [Syntax] (DESIGN.md, section 5; the paper's Figures 7, 8, 11), or fails
    with a message naming the culprit.  It first checks that the model is
    well formed ([Wellformed.wf_check], equivalent to the boolean
    [Wellformed.wf]), then builds the program with total functions
    ([build_program]).  The names it gives to functions, globals and
    temporaries, and its lookup tables, are fixed in [Wellformed], since
    the rules are about them.  Its properties are proved in
    [Generatorspec] and [Generatorproof].

    The generated program, for a node whose subscribed topics have C names
    [s1 ... sk] and published topics [p1 ... pl]:
<<
    struct M { ... };                      one per message definition
    struct ExtU_Controller_T { ... };      the controller's inputs
    struct ExtY_Controller_T { ... };      the controller's outputs
    extern void ros_init(void); int ros_ok(void); void ros_spinOnce(void);
    void ros_rate_sleep(void);              period: EF_ros_rate_sleep nm_period_ms
    void ros_subscribe_si(void ( *cb)(struct M * ));      per subscribed topic
    void ros_advertise_pj(void); void ros_publish_pj(struct M * );  per published topic
    void Controller_initialize(void); void Controller_step(void);
    struct ExtU_Controller_T Controller_U; struct ExtY_Controller_T Controller_Y;
    struct M si_msg;                       per subscribed topic
    void si_callback(struct M *msg) { ...copy the leaves of *msg that the node reads into si_msg,
                                      or, for a direct relation (rule 4.16), into Controller_U... }
    void input_glue(void) { ...one copy per input relation that is not direct... }
    void output_glue_pj(struct M *command) { ...zero *command, one copy per output relation... }
    void loop(void) { struct M pj_cmd; ...
      for (;;) { _ok = ros_ok(); if (_ok) ; else break; ros_spinOnce(); input_glue();
                 Controller_step(); output_glue_pj(&pj_cmd); ros_publish_pj(&pj_cmd); ...
                 ros_rate_sleep(); } }
    int main(void) { ros_init(); Controller_initialize(); ros_subscribe_si(&si_callback); ...
                     ros_advertise_pj(); ... loop(); return 0; }
>>
    Every copy goes through a temporary named after its C type, as in the
    paper's Figure 14: [_t_double = src; dst = _t_double;].  Function
    parameters ([msg], [command]) are temporaries ([Etempvar]). *)

From Coq Require Import String Ascii List ZArith Bool.
From Flocq Require Import IEEE754.Binary.
From ROSGen Require Import Errors Syntax Values Maps NodeModel Wellformed.
Import ListNotations.

Local Open Scope string_scope.
Local Open Scope list_scope.
Local Open Scope error_monad_scope.

(** ** Temporaries *)

(** The temporaries needed to copy values of the primitives [qs], in the
    order of [all_temps]. *)
Definition temps_of (qs : list prim) : list (ident * type) :=
  filter (fun xt => existsb (fun q => ident_eqb (temp_name q) (fst xt)) qs) all_temps.

(** ** Composite types *)

(** The structs of the model, [composites m] (messages, then the
    controller's inputs and outputs), are defined in [NodeModel]. *)

(** ** Path expressions *)

(** The type of member [f] of [struct id]. *)
Definition field_type (ce : list composite_definition) (id f : ident) : option type :=
  match find_composite id ce with
  | Some co => find_assoc f (co_members co)
  | None => None
  end.

(** The C type reached by following a path from type [t]. *)
Fixpoint type_of_path (ce : list composite_definition) (t : type) (p : path) : option type :=
  match p with
  | [] => Some t
  | PField f :: p' =>
      match t with
      | Tstruct id =>
          match field_type ce id f with
          | Some t' => type_of_path ce t' p'
          | None => None
          end
      | _ => None
      end
  | PIndex i :: p' =>
      match t with
      | Tarray t' n => if (0 <=? i)%Z && (i <? n)%Z then type_of_path ce t' p' else None
      | _ => None
      end
  end.

(** The type of one step from type [t] ([Tvoid] if it does not resolve,
    which never happens for well-formed models). *)
Definition step_type (ce : list composite_definition) (t : type) (s : pstep) : type :=
  match s, t with
  | PField f, Tstruct id =>
      match field_type ce id f with Some t' => t' | None => Tvoid end
  | PIndex _, Tarray t' _ => t'
  | _, _ => Tvoid
  end.

(** [e.f] or [e[i]]. *)
Definition step_expr (ce : list composite_definition) (e : expr) (s : pstep) : expr :=
  match s with
  | PField f => Efield e f (step_type ce (typeof e) s)
  | PIndex i => Eindex e (Econst_int i tint) (step_type ce (typeof e) s)
  end.

(** The expression [e.p] for a path [p]: [( *msg).twist.linear.x]. *)
Fixpoint path_expr (ce : list composite_definition) (e : expr) (p : path) : expr :=
  match p with
  | [] => e
  | s :: p' => path_expr ce (step_expr ce e s) p'
  end.

(** ** Statement templates *)

(** The copy template of the paper's Figure 14: [tmp = src; dst = tmp;]. *)
Definition copy (q : prim) (dst src : expr) : statement :=
  Ssequence (Sset (temp_name q) src)
            (Sassign dst (Etempvar (temp_name q) (ctype_of_prim q))).

(** [s1; s2; ...; sn; skip]. *)
Definition seq_of (l : list statement) : statement := fold_right Ssequence Sskip l.

(** [f();] for a function [f] of type [void(void)]. *)
Definition call0 (f : ident) : statement :=
  Scall None (Evar f (Tfunction [] Tvoid)) [].

(** The zero of a primitive's C type ([+0.0] for floats). *)
Definition zero_of (q : prim) : expr :=
  match q with
  | Pint64 | Puint64 => Econst_long 0 (ctype_of_prim q)
  | Pfloat32 => Econst_single (B754_zero 24 128 false) (ctype_of_prim q)
  | Pfloat64 => Econst_float (B754_zero 53 1024 false) (ctype_of_prim q)
  | _ => Econst_int 0 (ctype_of_prim q)
  end.

(** Copy leaf [l] of [src] into the same leaf of [dst]. *)
Definition leaf_copy (ce : list composite_definition) (dst src : expr) (l : path * prim) : statement :=
  copy (snd l) (path_expr ce dst (fst l)) (path_expr ce src (fst l)).

(** Zero leaf [l] of [dst]. *)
Definition leaf_zero (ce : list composite_definition) (dst : expr) (l : path * prim) : statement :=
  Sassign (path_expr ce dst (fst l)) (zero_of (snd l)).

(** [*x] for a parameter [x] of type [struct M *]. *)
Definition deref_param (x M : ident) : expr := Ederef (Etempvar x (tptr (Tstruct M))) (Tstruct M).

(** The type of a callback on messages [M], and of [&c_cmd]. *)
Definition callback_type (M : ident) : type := Tfunction [tptr (Tstruct M)] Tvoid.

Section GENERATION.

Variable m : node_model.

Let ce := composites m.

(** ** Lookups with defaults (never used for well-formed models) *)

Variable tb : tables.

(** The message type of the topic with C name [c]. *)
Definition topic_msg (c : ident) : ident :=
  match lookup_topic tb c with Some tp => tp_msg tp | None => "" end.

(** The primitive of the leaf [p] of a controller input / output field [x]. *)
Definition leaf_prim (ot : option ftype) (p : path) : prim :=
  match ot with
  | Some t => match ctrl_prim t p with Some q => q | None => Pbool end
  | None => Pbool
  end.
Definition input_prim (x : ident) (p : path) : prim := leaf_prim (tget (enc_string x) (tb_inputs tb)) p.
Definition output_prim (x : ident) (p : path) : prim := leaf_prim (tget (enc_string x) (tb_outputs tb)) p.

(** The output relations of the topic with C name [c], in order. *)
Definition topic_outrels (c : ident) : list outrel :=
  tget_default [] (enc_string c) (tb_outrels tb).

(** The variables [Controller_U], [Controller_Y]. *)
Definition in_var_expr : expr := Evar (nm_in_var m) (Tstruct (nm_in_struct m)).
Definition out_var_expr : expr := Evar (nm_out_var m) (Tstruct (nm_out_struct m)).

(** ** Callbacks (Figure 11) *)

(** The C types of a timed topic's clock (rule 4.12). *)
Definition tulong : type := Tlong Unsigned.
Definition tflag : type := ctype_of_prim Pbool.

Definition time_expr (c : ident) : expr := Evar (time_var c) tulong.
Definition new_expr (c : ident) : expr := Evar (new_var c) tflag.
Definition rcvd_expr (c : ident) : expr := Evar (rcvd_var c) tflag.

(** [_t_ullong = ros_now();] *)
Definition now_call (x : ident) : statement :=
  Scall (Some x) (Evar ros_now_name (Tfunction [] tulong)) [].

(** The clock update of a timed topic's callback:
    [_t_ullong = ros_now(); c_time = _t_ullong; c_new = 1; c_rcvd = 1;]. *)
Definition clock_stmts (c : ident) : statement :=
  seq_of [now_call (temp_name Puint64);
          Sassign (time_expr c) (Etempvar (temp_name Puint64) tulong);
          Sassign (new_expr c) (Econst_int 1 tflag);
          Sassign (rcvd_expr c) (Econst_int 1 tflag)].

(** ** Input glue (Figures 8, 14) *)

(** Source and destination of the copy for an input relation: the leaf
    [ir_path] of [c_msg] and the leaf [ir_elem] of the field [ir_input]
    of [Controller_U] ([Controller_U.In1], [Controller_U.Scan[540]]). *)
Definition input_src (ir : inrel) : expr :=
  path_expr ce (Evar (msg_var (ir_topic ir)) (Tstruct (topic_msg (ir_topic ir)))) (ir_path ir).
Definition input_dst (ir : inrel) : expr :=
  path_expr ce in_var_expr (PField (ir_input ir) :: ir_elem ir).

(** The primitive that an input relation copies. *)
Definition inrel_prim (ir : inrel) : prim := input_prim (ir_input ir) (ir_elem ir).

Definition input_copy (ir : inrel) : statement :=
  copy (inrel_prim ir) (input_dst ir) (input_src ir).

(** ** Callbacks (continued) *)

(** The leaves of topic [tp]'s messages that the glue keeps in its
    global [c_msg] ([read_paths]), in the order of [leaves]. *)
Definition read_leaves (tp : topic) : list (path * prim) :=
  filter (fun l => is_read m (tp_cname tp) (fst l)) (leaves (nm_msgs m) (tp_msg tp)).

(** The copy of a direct input relation (rule 4.16), in the callback of
    its topic: from the leaf [ir_path] of [*msg] into [Controller_U]. *)
Definition direct_copy (M : ident) (ir : inrel) : statement :=
  copy (inrel_prim ir) (input_dst ir) (path_expr ce (deref_param msg_param M) (ir_path ir)).

(** [void c_callback(struct M *msg)]: copy into [c_msg] the leaves of
    [*msg] that the glue keeps there; then, if the topic is timed, update
    its clock, else copy the leaves of its direct input relations into
    [Controller_U] (rule 4.16; nothing for a topic without any). *)
Definition callback_function (tp : topic) : function :=
  let M := tp_msg tp in
  let lv := read_leaves tp in
  let body := seq_of (map (leaf_copy ce (Evar (msg_var (tp_cname tp)) (Tstruct M))
                                       (deref_param msg_param M)) lv) in
  if is_timed m (tp_cname tp)
  then mkfunction Tvoid [(msg_param, tptr (Tstruct M))] [] (temps_of (Puint64 :: map snd lv))
         (Ssequence body (clock_stmts (tp_cname tp)))
  else match direct_of m (tp_cname tp) with
       | [] => mkfunction Tvoid [(msg_param, tptr (Tstruct M))] [] (temps_of (map snd lv)) body
       | ds => mkfunction Tvoid [(msg_param, tptr (Tstruct M))] [] (temps_of (map snd lv ++ map inrel_prim ds))
                 (Ssequence body (seq_of (map (direct_copy M) ds)))
       end.

(** *** Freshness (rule 4.12) *)

(** [_age]: the age in nanoseconds of the newest message of timed topic
    [c] at the cycle's time [_now], 0 if the clock went back, the
    largest [unsigned long long] if no message arrived yet:
<<
    if (c_rcvd) { if (c_time <= _now) _age = _now - c_time; else _age = 0; }
    else _age = 18446744073709551615ULL;
>> *)
Definition max_ulong : Z := 18446744073709551615.

Definition age_stmt (c : ident) : statement :=
  let now := Etempvar now_temp tulong in
  Sifthenelse (rcvd_expr c)
    (Sifthenelse (Ebinop Ole (time_expr c) now tint)
       (Sset age_temp (Ebinop Osub now (time_expr c) tulong))
       (Sset age_temp (Econst_long 0 tulong)))
    (Sset age_temp (Econst_long max_ulong tulong)).

(** The constant expression of a fallback value. *)
Definition const_of (q : prim) (v : val) : expr :=
  match v with
  | Vlong n => Econst_long n (ctype_of_prim q)
  | Vfloat f => Econst_float f (ctype_of_prim q)
  | Vsingle f => Econst_single f (ctype_of_prim q)
  | Vint n => Econst_int n (ctype_of_prim q)
  | _ => zero_of q
  end.

(** A stale topic: [timeout * 1000000ULL < _age]. *)
Definition stale_expr (t : Z) : expr :=
  Ebinop Olt (Econst_long (t * 1000000) tulong) (Etempvar age_temp tulong) tint.

(** The fallback of an input relation whose input has one: the age of
    its topic's newest message, then [if (T < _age) U.In = v;]. *)
Definition fallback_stmt (ir : inrel) : statement :=
  match find_assoc (ir_input ir) (nm_fallbacks m), timeout_of m (ir_topic ir) with
  | Some v, Some t =>
      Ssequence (age_stmt (ir_topic ir))
        (Sifthenelse (stale_expr t) (Sassign (input_dst ir) (const_of (inrel_prim ir) v)) Sskip)
  | _, _ => Sskip
  end.

(** The input relations with a fallback, in model order. *)
Definition has_fallback (ir : inrel) : bool :=
  match find_assoc (ir_input ir) (nm_fallbacks m) with Some _ => true | None => false end.

(** The largest age, in ns, whose milliseconds fit in [uint32]. *)
Definition max_age_ns : Z := 4294967295999999.
Definition max_uint : Z := 4294967295.

(** [U.In = e] for a derived input [In]. *)
Definition derived_dst (dr : drel) : expr :=
  Efield in_var_expr (dr_input dr) (ctype_of_prim (input_prim (dr_input dr) [])).

(** A derived input: [is_new] and [received] copy the flags; [age_ms] is
    the age of the topic's newest message, then
<<
    if (_age <= 4294967295999999ULL) U.In = (unsigned int)(_age / 1000000ULL);
    else U.In = 4294967295U;
>> *)
Definition derived_stmt (dr : drel) : statement :=
  let c := dr_topic dr in
  match dr_kind dr with
  | Dis_new => copy Pbool (derived_dst dr) (new_expr c)
  | Dreceived => copy Pbool (derived_dst dr) (rcvd_expr c)
  | Dage_ms =>
      let age := Etempvar age_temp tulong in
      Ssequence (age_stmt c)
        (Sifthenelse (Ebinop Ole age (Econst_long max_age_ns tulong) tint)
           (Sassign (derived_dst dr) (Ecast (Ebinop Odiv age (Econst_long 1000000 tulong) tulong) tuint))
           (Sassign (derived_dst dr) (Econst_int max_uint tuint)))
  end.

(** [c_new = 0;] *)
Definition reset_stmt (tp : topic) : statement := Sassign (new_expr (tp_cname tp)) (Econst_int 0 tflag).

(** Whether a derived input is an age (else it copies a flag). *)
Definition is_age (dr : drel) : bool :=
  match dr_kind dr with Dage_ms => true | _ => false end.

(** Whether [input_glue] reads an age (some fallback or [age_ms]): only
    then does it read the cycle's time into [_now] and declare [_now] and
    [_age]; and whether it copies a flag (then it declares [_t_uchar]).
    A temporary that is declared but not read is refused by the build's
    [gcc -Wall -Werror]. *)
Definition reads_age : bool :=
  existsb has_fallback (nm_inrels m) || existsb is_age (nm_drels m).
Definition reads_flag : bool :=
  existsb (fun dr => negb (is_age dr)) (nm_drels m).

(** After the copies: [_now = ros_now();] (if an age is read), the
    fallbacks (in the order of the input relations), the derived inputs
    (in model order), then the [c_new] flags of the timed topics
    cleared. *)
Definition timed_stmts : statement :=
  seq_of ((if reads_age then [now_call now_temp] else [])
          ++ map fallback_stmt (filter has_fallback (nm_inrels m))
          ++ map derived_stmt (nm_drels m)
          ++ map reset_stmt (timed m)).

(** The temporaries of [input_glue] when some topic is timed. *)
Definition timed_temps : list (ident * type) :=
  (if reads_age then [(now_temp, tulong); (age_temp, tulong)] else [])
  ++ temps_of ((if reads_flag then [Pbool] else []) ++ map inrel_prim (glue_inrels m)).

(** [void input_glue(void)]: one copy per input relation that is not
    direct (rule 4.16), in order; then, if some topic is timed, the
    freshness. *)
Definition input_glue_function : function :=
  let temps := temps_of (map inrel_prim (glue_inrels m)) in
  let base := seq_of (map input_copy (glue_inrels m)) in
  match timed m with
  | [] => mkfunction Tvoid [] [] temps base
  | _ :: _ => mkfunction Tvoid [] [] timed_temps (Ssequence base timed_stmts)
  end.

(** ** Output glue (Figure 8) *)

(** Source and destination of the copy for an output relation: the leaf
    [or_elem] of the field [or_output] of [Controller_Y] and the leaf
    [or_path] of [*command]. *)
Definition output_src (o : outrel) : expr :=
  path_expr ce out_var_expr (PField (or_output o) :: or_elem o).
Definition output_dst (M : ident) (o : outrel) : expr :=
  path_expr ce (deref_param command_param M) (or_path o).

(** The primitive that an output relation copies. *)
Definition outrel_prim (o : outrel) : prim := output_prim (or_output o) (or_elem o).

Definition output_copy (M : ident) (o : outrel) : statement :=
  copy (outrel_prim o) (output_dst M o) (output_src o).

(** The stamp path of the topic with C name [c], if it is stamped. *)
Definition topic_stamp (c : ident) : option path := find_assoc c (nm_stamps m).

(** The [uint32] temporary and a time function's call. *)
Definition tuint : type := Tint I32 Unsigned.
Definition time_call (f : ident) : statement :=
  Scall (Some (temp_name Puint32)) (Evar f (Tfunction [] tuint)) [].

(** The source of the stamp of the topic with C name [c], if it is
    copied from a subscribed topic. *)
Definition topic_stamp_from (c : ident) : option (ident * path) := find_assoc c (nm_stamp_from m).

(** The seconds of the ROS time, [_t_uint], stored into the stamp's
    [sec]: as they are into ROS 1's [uint32], converted to [int] for
    ROS 2's [int32] (modulo 2^32: past 2038 the value is negative, as
    gcc's conversion makes it). *)
Definition stamp_sec_expr : expr :=
  if time_is_ros2 (nm_msgs m) then Ecast (Etempvar (temp_name Puint32) tuint) (Tint I32 Signed)
  else Etempvar (temp_name Puint32) tuint.

(** [_t_uint = ros_time_sec(); command->sp.sec = _t_uint;
     _t_uint = ros_time_nsec(); command->sp.nsec = _t_uint;], or for a
    stamp copied from the subscribed topic [s] at path [sp']:
    [_t_uint = s_msg.sp'.sec; command->sp.sec = _t_uint;] and the same
    for [nsec].  On ROS 2 ([NodeModel.time_is_ros2]) the seconds are
    stored as [(int)_t_uint] and copied through [_t_int], and [nsec] is
    [nanosec]. *)
Definition stamp_stmts (c M : ident) (sp : path) : statement :=
  let dst f := path_expr ce (deref_param command_param M) (sp ++ [PField f]) in
  let nf := time_nsec_field (nm_msgs m) in
  match topic_stamp_from c with
  | None =>
      seq_of [time_call ros_time_sec_name;
              Sassign (dst "sec") stamp_sec_expr;
              time_call ros_time_nsec_name;
              Sassign (dst nf) (Etempvar (temp_name Puint32) tuint)]
  | Some (s, sp') =>
      let src f := path_expr ce (Evar (msg_var s) (Tstruct (topic_msg s))) (sp' ++ [PField f]) in
      seq_of [copy (time_sec_prim (nm_msgs m)) (dst "sec") (src "sec"); copy Puint32 (dst nf) (src nf)]
  end.

(** The temporaries of the stamp of the topic with C name [c]: [_t_uint],
    and the seconds' ([_t_int] on ROS 2) if the stamp is copied. *)
Definition stamp_prims (c : ident) : list prim :=
  Puint32 :: match topic_stamp_from c with Some _ => [time_sec_prim (nm_msgs m)] | None => [] end.

(** The constant strings of the topic with C name [c] (rule 4.14): each
    string's path and bytes, in model order. *)
Definition topic_strings (c : ident) : list (path * list Z) :=
  map snd (filter (fun st => ident_eqb (fst st) c) (nm_strings m)).

(** The leaves that a constant string [bs] at path [sp] writes, with
    their values: [sp.len] the number of bytes, [sp.data[i]] the [i]-th
    byte. *)
Definition string_stores (sp : path) (bs : list Z) : list (path * prim * Z) :=
  (sp ++ [PField "len"], Puint32, Z.of_nat (length bs))
  :: map (fun ib => (sp ++ [PField "data"; PIndex (fst ib)], Puint8, snd ib))
         (combine (zrange (Z.of_nat (length bs))) bs).

(** [command->lp = v;] *)
Definition const_store (M : ident) (a : path * prim * Z) : statement :=
  Sassign (path_expr ce (deref_param command_param M) (fst (fst a))) (Econst_int (snd a) (ctype_of_prim (snd (fst a)))).

(** The stores of the constant strings of the topic with C name [c]. *)
Definition topic_stores (c : ident) : list (path * prim * Z) :=
  flat_map (fun sb => string_stores (fst sb) (snd sb)) (topic_strings c).

Definition strings_stmts (c M : ident) : statement :=
  seq_of (map (const_store M) (topic_stores c)).

(** [void output_glue_c(struct M *command)]: zero every leaf of
    [*command], then one copy per output relation of the topic, then,
    if the topic is stamped, the stamp, then the constant strings. *)
Definition output_glue_function (tp : topic) : function :=
  let M := tp_msg tp in
  let os := topic_outrels (tp_cname tp) in
  let qs := map outrel_prim os in
  let body := Ssequence (seq_of (map (leaf_zero ce (deref_param command_param M)) (leaves (nm_msgs m) M)))
                        (seq_of (map (output_copy M) os)) in
  let strs := strings_stmts (tp_cname tp) M in
  match topic_stamp (tp_cname tp) with
  | None => mkfunction Tvoid [(command_param, tptr (Tstruct M))] [] (temps_of qs) (Ssequence body strs)
  | Some sp => mkfunction Tvoid [(command_param, tptr (Tstruct M))] [] (temps_of (stamp_prims (tp_cname tp) ++ qs))
                 (Ssequence (Ssequence body (stamp_stmts (tp_cname tp) M sp)) strs)
  end.

(** ** The loop and main (Figures 2, 7) *)

(** [&c_cmd]. *)
Definition cmd_addr (tp : topic) : expr :=
  Eaddrof (Evar (cmd_var (tp_cname tp)) (Tstruct (tp_msg tp))) (tptr (Tstruct (tp_msg tp))).

(** [output_glue_c(&c_cmd); ros_publish_c(&c_cmd);] *)
Definition publish_stmts (tp : topic) : list statement :=
  [Scall None (Evar (output_glue_name (tp_cname tp)) (callback_type (tp_msg tp))) [cmd_addr tp];
   Scall None (Evar (publish_name (tp_cname tp)) (callback_type (tp_msg tp))) [cmd_addr tp]].

(** The statements of one cycle of the loop, the first two being the
    loop's exit test. *)
Definition loop_stmts : list statement :=
  [Scall (Some ok_temp) (Evar ros_ok_name (Tfunction [] tint)) [];
   Sifthenelse (Etempvar ok_temp tint) Sskip Sbreak;
   call0 ros_spinOnce_name;
   call0 input_glue_name;
   call0 (step_name m)]
  ++ flat_map publish_stmts (published m)
  ++ [call0 ros_rate_sleep_name].

(** [void loop(void)], with one local message [c_cmd] per published topic. *)
Definition loop_function : function :=
  mkfunction Tvoid []
    (map (fun tp => (cmd_var (tp_cname tp), Tstruct (tp_msg tp))) (published m))
    [(ok_temp, tint)]
    (Sloop (seq_of loop_stmts)).

(** [ros_subscribe_c(&c_callback);] *)
Definition subscribe_stmt (tp : topic) : statement :=
  Scall None (Evar (subscribe_name (tp_cname tp)) (Tfunction [tptr (callback_type (tp_msg tp))] Tvoid))
    [Eaddrof (Evar (callback_name (tp_cname tp)) (callback_type (tp_msg tp)))
             (tptr (callback_type (tp_msg tp)))].

(** [ros_advertise_c();] *)
Definition advertise_stmt (tp : topic) : statement := call0 (advertise_name (tp_cname tp)).

Definition main_stmts : list statement :=
  [call0 ros_init_name; call0 (init_name m)]
  ++ map subscribe_stmt (subscribed m)
  ++ map advertise_stmt (published m)
  ++ [call0 loop_name; Sreturn (Some (Econst_int 0 tint))].

(** [int main(void)]. *)
Definition main_function : function :=
  mkfunction tint [] [] [] (seq_of main_stmts).

(** ** Global definitions *)

(** The time functions: [ros_now], declared by a node with a timed
    topic, the stamp functions, by a node that stamps messages. *)
Definition now_externals : list (ident * globdef) :=
  match timed m with
  | [] => []
  | _ :: _ => [(ros_now_name, Gfun (External EF_ros_now [] tulong))]
  end.

Definition stamp_externals : list (ident * globdef) :=
  match nm_stamps m with
  | [] => []
  | _ :: _ => [(ros_time_sec_name, Gfun (External EF_ros_time_sec [] tuint));
               (ros_time_nsec_name, Gfun (External EF_ros_time_nsec [] tuint))]
  end.

Definition time_externals : list (ident * globdef) := now_externals ++ stamp_externals.

(** The ROS API functions that do not depend on the topics ([ros_rate_sleep]
    carries the node's period), and the time functions if needed. *)
Definition ros_externals : list (ident * globdef) :=
  [(ros_init_name, Gfun (External EF_ros_init [] Tvoid));
   (ros_ok_name, Gfun (External EF_ros_ok [] tint));
   (ros_spinOnce_name, Gfun (External EF_ros_spinOnce [] Tvoid));
   (ros_rate_sleep_name, Gfun (External (EF_ros_rate_sleep (nm_period_ms m)) [] Tvoid))]
  ++ time_externals.

(** The ROS API functions of a topic. *)
Definition topic_externals (tp : topic) : list (ident * globdef) :=
  match tp_dir tp with
  | Subscribe =>
      [(subscribe_name (tp_cname tp),
        Gfun (External (EF_ros_subscribe (tp_name tp) (tp_msg tp) (tp_queue tp))
                       [tptr (callback_type (tp_msg tp))] Tvoid))]
  | Publish =>
      [(advertise_name (tp_cname tp),
        Gfun (External (EF_ros_advertise (tp_name tp) (tp_msg tp) (tp_queue tp)) [] Tvoid));
       (publish_name (tp_cname tp),
        Gfun (External (EF_ros_publish (tp_name tp) (tp_msg tp)) [tptr (Tstruct (tp_msg tp))] Tvoid))]
  end.

(** The controller's functions and its two global structs (defined by the
    controller's own C file). *)
Definition controller_defs : list (ident * globdef) :=
  [(init_name m, Gfun (External (EF_controller_initialize (nm_in_var m) (nm_out_var m)) [] Tvoid));
   (step_name m, Gfun (External (EF_controller_step (nm_in_var m) (nm_out_var m)) [] Tvoid));
   (nm_in_var m, Gvar (Tstruct (nm_in_struct m)));
   (nm_out_var m, Gvar (Tstruct (nm_out_struct m)))].

Definition msg_global (tp : topic) : ident * globdef :=
  (msg_var (tp_cname tp), Gvar (Tstruct (tp_msg tp))).

(** The clock globals of a timed topic. *)
Definition clock_globals (tp : topic) : list (ident * globdef) :=
  [(time_var (tp_cname tp), Gvar tulong);
   (new_var (tp_cname tp), Gvar tflag);
   (rcvd_var (tp_cname tp), Gvar tflag)].

Definition callback_def (tp : topic) : ident * globdef :=
  (callback_name (tp_cname tp), Gfun (Internal (callback_function tp))).

Definition output_glue_def (tp : topic) : ident * globdef :=
  (output_glue_name (tp_cname tp), Gfun (Internal (output_glue_function tp))).

(** All global definitions, declarations before uses. *)
Definition build_defs : list (ident * globdef) :=
  ros_externals
  ++ flat_map topic_externals (nm_topics m)
  ++ controller_defs
  ++ map msg_global (subscribed m)
  ++ flat_map clock_globals (timed m)
  ++ map callback_def (subscribed m)
  ++ [(input_glue_name, Gfun (Internal input_glue_function))]
  ++ map output_glue_def (published m)
  ++ [(loop_name, Gfun (Internal loop_function));
      (main_name, Gfun (Internal main_function))].

End GENERATION.

(** The program, with the lookup tables built once. *)
Definition build_program (m : node_model) : program :=
  mkprogram (composites m) (build_defs m (make_tables m)) main_name.

(** ** The generator *)

(** [wf_check] first (it names the culprit of a refusal), then the
    program. *)
Definition generate (m : node_model) : res program :=
  do _ <- wf_check m;
  OK (build_program m).

(** ** Former names *)

(** The rules used to be defined in this file; [Generator.wf] and
    [Generator.wf_check] still name [Wellformed.wf] and
    [Wellformed.wf_check], for per-node files written before the move. *)
Notation wf := Wellformed.wf (only parsing).
Notation wf_check := Wellformed.wf_check (only parsing).
