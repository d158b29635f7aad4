(** * Example programs run by the interpreter *)

(** Small programs of the Clight subset, run by [Interp.run_program]
    under [vm_compute]; each [Example] states the exact result.  At the
    end, the big-step semantics is shown to hold for the mini-node through
    the interpreter's soundness theorem (T5). *)

From Coq Require Import String List ZArith.
From Flocq Require Import IEEE754.Binary.
From ROSGen Require Import Syntax Values Memory Environment Semantics Typing Interp Interpproof.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope Z_scope.

(** ** Helpers *)

(** The whole value of global [x] in memory [m]. *)
Definition read_global (p : program) (m : mem) (x : ident) : option mval :=
  match find_var (globalenv p) x with
  | Some (b, _) => load_path m b []
  | None => None
  end.

(** Run [main] and read some globals afterwards. *)
Definition run_and_read {CS : Type} (p : program) (ctx : ros_context CS) (n : nat) (xs : list ident)
  : option (val * list (option mval)) :=
  match run_program 4000 p ctx n with
  | Some (_, v, m, _) => Some (v, map (read_global p m) xs)
  | None => None
  end.

(** A context without messages and with a controller that does nothing. *)
Definition quiet_ctx : ros_context unit :=
  mkctx (fun _ => []) (fun _ => 0%Z) tt (fun s u => (s, u)) Ros1.

Definition sc (v : val) : mval := MVscalar v.
Definition ndouble : float64 := B754_zero 53 1024 true.   (**r -0.0 *)
Definition pdouble : float64 := B754_zero 53 1024 false.  (**r +0.0 *)

Definition fn (ret : type) (params vars temps : list (ident * type)) (body : statement) : globdef :=
  Gfun (Internal (mkfunction ret params vars temps body)).

Fixpoint seq (l : list statement) : statement :=
  match l with
  | [] => Sskip
  | [s] => s
  | s :: l' => Ssequence s (seq l')
  end.

Definition ret0 : statement := Sreturn (Some (Econst_int 0 tint)).

(** ** Struct copy through a pointer argument, nested fields *)

(** [struct A { int b; double c; };
     struct M { struct A a; unsigned char x; };
     int g_b; struct M g_copy;
     void cb(struct M *msg) { int t; t = ( *msg).a.b; g_b = t; g_copy = *msg; }
     int main(void) { struct M loc;
       loc.a.b = 42; loc.a.c = -0.0; loc.x = (unsigned char) 300;
       cb(&loc); return 0; }] *)

Definition tA := Tstruct "A".
Definition tM := Tstruct "M".
Definition comp_A := Composite "A" [("b", tint); ("c", tdouble)].
Definition comp_M := Composite "M" [("a", tA); ("x", tuchar)].
Definition cb_type := Tfunction [tptr tM] Tvoid.
Definition msg := Etempvar "msg" (tptr tM).

Definition prog_copy : program := {|
  prog_types := [comp_A; comp_M];
  prog_defs := [
    ("g_b", Gvar tint);
    ("g_copy", Gvar tM);
    ("cb", fn Tvoid [("msg", tptr tM)] [] [("t", tint)] (seq [
       Sset "t" (Efield (Efield (Ederef msg tM) "a" tA) "b" tint);
       Sassign (Evar "g_b" tint) (Etempvar "t" tint);
       Sassign (Evar "g_copy" tM) (Ederef msg tM);
       Sreturn None]));
    ("main", fn tint [] [("loc", tM)] [] (seq [
       Sassign (Efield (Efield (Evar "loc" tM) "a" tA) "b" tint) (Econst_int 42 tint);
       Sassign (Efield (Efield (Evar "loc" tM) "a" tA) "c" tdouble) (Econst_float ndouble tdouble);
       Sassign (Efield (Evar "loc" tM) "x" tuchar) (Ecast (Econst_int 300 tint) tuchar);
       Scall None (Evar "cb" cb_type) [Eaddrof (Evar "loc" tM) (tptr tM)];
       ret0]))];
  prog_main := "main" |}.

Example copy_result:
  run_and_read prog_copy quiet_ctx 0 ["g_b"; "g_copy"]
  = Some (Vint 0,
          [Some (sc (Vint 42));
           Some (MVstruct [("a", MVstruct [("b", sc (Vint 42)); ("c", sc (Vfloat ndouble))]);
                           ("x", sc (Vint 44))])]).
Proof. vm_compute. reflexivity. Qed.

(** Globals start zero-initialised: without the call, [g_copy] is zero. *)
Definition prog_nocall : program :=
  {| prog_types := prog_types prog_copy;
     prog_defs := prog_defs prog_copy ++ [("main2", fn tint [] [] [] ret0)];
     prog_main := "main2" |}.

Example zero_init:
  run_and_read prog_nocall quiet_ctx 0 ["g_b"; "g_copy"]
  = Some (Vint 0,
          [Some (sc (Vint 0));
           Some (MVstruct [("a", MVstruct [("b", sc (Vint 0)); ("c", sc (Vfloat pdouble))]);
                           ("x", sc (Vint 0))])]).
Proof. vm_compute. reflexivity. Qed.

(** ** Arrays *)

(** [struct P { int arr[3]; struct A in; }; struct P g_p;
     int main(void) { int t; g_p.arr[2] = 9; g_p.in.b = 7;
       t = g_p.arr[2]; g_p.arr[0] = t; return t; }] *)

Definition tP := Tstruct "P".
Definition comp_P := Composite "P" [("arr", Tarray tint 3); ("in", tA)].
Definition arr := Efield (Evar "g_p" tP) "arr" (Tarray tint 3).

Definition prog_array (bad_index : Z) : program := {|
  prog_types := [comp_A; comp_P];
  prog_defs := [
    ("g_p", Gvar tP);
    ("main", fn tint [] [] [("t", tint)] (seq [
       Sassign (Eindex arr (Econst_int 2 tint) tint) (Econst_int 9 tint);
       Sassign (Efield (Efield (Evar "g_p" tP) "in" tA) "b" tint) (Econst_int 7 tint);
       Sset "t" (Eindex arr (Econst_int 2 tint) tint);
       Sassign (Eindex arr (Econst_int bad_index tint) tint) (Etempvar "t" tint);
       Sreturn (Some (Etempvar "t" tint))]))];
  prog_main := "main" |}.

Example array_result:
  run_and_read (prog_array 0) quiet_ctx 0 ["g_p"]
  = Some (Vint 9,
          [Some (MVstruct [("arr", MVarray [sc (Vint 9); sc (Vint 0); sc (Vint 9)]);
                           ("in", MVstruct [("b", sc (Vint 7)); ("c", sc (Vfloat pdouble))])])]).
Proof. vm_compute. reflexivity. Qed.

(** An index out of bounds is undefined: the run is stuck. *)
Example array_out_of_bounds: run_and_read (prog_array 3) quiet_ctx 0 ["g_p"] = None.
Proof. vm_compute. reflexivity. Qed.

Example array_negative_index: run_and_read (prog_array (-1)) quiet_ctx 0 ["g_p"] = None.
Proof. vm_compute. reflexivity. Qed.

(** ** Loops and break *)

(** [int g; int main(void) { for (;;) { g = 5; break; g = 6; } return g; }] *)
Definition prog_break : program := {|
  prog_types := [];
  prog_defs := [
    ("g", Gvar tint);
    ("main", fn tint [] [] [] (seq [
       Sloop (seq [Sassign (Evar "g" tint) (Econst_int 5 tint); Sbreak;
                   Sassign (Evar "g" tint) (Econst_int 6 tint)]);
       Sreturn (Some (Evar "g" tint))]))];
  prog_main := "main" |}.

Example break_result: run_and_read prog_break quiet_ctx 0 ["g"] = Some (Vint 5, [Some (sc (Vint 5))]).
Proof. vm_compute. reflexivity. Qed.

(** [int main(void) { int ok; for (;;) { ok = ros_ok(); if (ok) ; else break;
       ros_rate_sleep(); } return 0; }], with a period of 10 ms: one
    [Esleep 10] per [true] answer. *)
Definition tvoidfun := Tfunction [] Tvoid.
Definition call0 (f : ident) := Scall None (Evar f tvoidfun) [].

Definition prog_okloop : program := {|
  prog_types := [];
  prog_defs := [
    ("ros_ok", Gfun (External EF_ros_ok [] tint));
    ("ros_rate_sleep", Gfun (External (EF_ros_rate_sleep 10) [] Tvoid));
    ("main", fn tint [] [] [("ok", tint)] (seq [
       Sloop (seq [Scall (Some "ok") (Evar "ros_ok" (Tfunction [] tint)) [];
                   Sifthenelse (Etempvar "ok" tint) Sskip Sbreak;
                   call0 "ros_rate_sleep"]);
       ret0]))];
  prog_main := "main" |}.

Example okloop_4: run_trace 100 prog_okloop quiet_ctx 4 = Some [Esleep 10; Esleep 10; Esleep 10; Esleep 10].
Proof. vm_compute. reflexivity. Qed.

Example okloop_0: run_trace 100 prog_okloop quiet_ctx 0 = Some [].
Proof. vm_compute. reflexivity. Qed.

(** Not enough fuel: no answer (rather than a wrong one). *)
Example okloop_fuel: run_trace 10 prog_okloop quiet_ctx 4 = None.
Proof. vm_compute. reflexivity. Qed.

(** ** Calls returning values, integer wrap-around *)

(** [unsigned char to_uchar(int a) { return a; }]  (300 -> 44)
    [unsigned int to_uint(int a) { return (unsigned int) a; }]  (-1 -> 4294967295)
    [signed char to_schar(int a) { return a; }]  (200 -> -56)
    [unsigned short to_ushort(int a) { unsigned short r; r = a; return r; }]  (70000 -> 4464)
    [long long to_long(unsigned int a) { return a; }]  (4294967295 -> 4294967295)
    [int main(void) { unsigned char c; ...; g_c = to_uchar(300); ...;
       g_k = (unsigned char) 511; return to_schar(200); }] *)

Definition tushort := Tint I16 Unsigned.
Definition tlong := Tlong Signed.

Definition prog_wrap : program := {|
  prog_types := [];
  prog_defs := [
    ("g_c", Gvar tuchar); ("g_u", Gvar tuint); ("g_s", Gvar tschar);
    ("g_h", Gvar tushort); ("g_l", Gvar tlong); ("g_k", Gvar tuchar);
    ("to_uchar", fn tuchar [("a", tint)] [] [] (Sreturn (Some (Etempvar "a" tint))));
    ("to_uint", fn tuint [("a", tint)] [] [] (Sreturn (Some (Ecast (Etempvar "a" tint) tuint))));
    ("to_schar", fn tschar [("a", tint)] [] [] (Sreturn (Some (Etempvar "a" tint))));
    ("to_ushort", fn tushort [("a", tint)] [("r", tushort)] [] (seq [
       Sassign (Evar "r" tushort) (Etempvar "a" tint);
       Sreturn (Some (Evar "r" tushort))]));
    ("to_long", fn tlong [("a", tuint)] [] [] (Sreturn (Some (Etempvar "a" tuint))));
    ("main", fn tint [] [] [("c", tuchar); ("u", tuint); ("s", tschar); ("h", tushort); ("l", tlong)] (seq [
       Scall (Some "c") (Evar "to_uchar" (Tfunction [tint] tuchar)) [Econst_int 300 tint];
       Sassign (Evar "g_c" tuchar) (Etempvar "c" tuchar);
       Scall (Some "u") (Evar "to_uint" (Tfunction [tint] tuint)) [Econst_int (-1) tint];
       Sassign (Evar "g_u" tuint) (Etempvar "u" tuint);
       Scall (Some "s") (Evar "to_schar" (Tfunction [tint] tschar)) [Econst_int 200 tint];
       Sassign (Evar "g_s" tschar) (Etempvar "s" tschar);
       Scall (Some "h") (Evar "to_ushort" (Tfunction [tint] tushort)) [Econst_int 70000 tint];
       Sassign (Evar "g_h" tushort) (Etempvar "h" tushort);
       Scall (Some "l") (Evar "to_long" (Tfunction [tuint] tlong)) [Etempvar "u" tuint];
       Sassign (Evar "g_l" tlong) (Etempvar "l" tlong);
       Sassign (Evar "g_k" tuchar) (Econst_int 511 tuchar);
       Sreturn (Some (Etempvar "s" tschar))]))];
  prog_main := "main" |}.

Example wrap_result:
  run_and_read prog_wrap quiet_ctx 0 ["g_c"; "g_u"; "g_s"; "g_h"; "g_l"; "g_k"]
  = Some (Vint (-56),
          [Some (sc (Vint 44)); Some (sc (Vint 4294967295)); Some (sc (Vint (-56)));
           Some (sc (Vint 4464)); Some (sc (Vlong 4294967295)); Some (sc (Vint 255))]).
Proof. vm_compute. reflexivity. Qed.

(** ** A mini ROS node *)

(** [struct In { int v; }; struct U { int In1; int In2; };
     struct Y { int Out1; }; struct Out { int cmd; };
     struct In sensor_msg; struct U Controller_U; struct Y Controller_Y;
     struct Out cmd_msg;
     void sensor_callback(struct In *msg) { int t; t = ( *msg).v; sensor_msg.v = t; }
     void input_glue(void) { int t; t = sensor_msg.v; Controller_U.In1 = t; }
     void output_glue(struct Out *command) { int t; t = Controller_Y.Out1; ( *command).cmd = t; }
     void loop(void) { int ok; while (ros_ok()) { ros_spinOnce(); input_glue();
       Controller_step(); output_glue(&cmd_msg); ros_publish_cmd(&cmd_msg);
       ros_rate_sleep(); } }
     int main(void) { ros_init(); Controller_initialize();
       ros_subscribe_sensor(&sensor_callback); ros_advertise_cmd(); loop(); return 0; }] *)

Definition tIn := Tstruct "In".
Definition tU := Tstruct "U".
Definition tY := Tstruct "Y".
Definition tOut := Tstruct "Out".
Definition sensor_cb_type := Tfunction [tptr tIn] Tvoid.

Definition node (queue : nat) : program := {|
  prog_types := [Composite "In" [("v", tint)];
                 Composite "U" [("In1", tint); ("In2", tint)];
                 Composite "Y" [("Out1", tint)];
                 Composite "Out" [("cmd", tint)]];
  prog_defs := [
    ("sensor_msg", Gvar tIn); ("Controller_U", Gvar tU);
    ("Controller_Y", Gvar tY); ("cmd_msg", Gvar tOut);
    ("ros_init", Gfun (External EF_ros_init [] Tvoid));
    ("ros_ok", Gfun (External EF_ros_ok [] tint));
    ("ros_spinOnce", Gfun (External EF_ros_spinOnce [] Tvoid));
    ("ros_rate_sleep", Gfun (External (EF_ros_rate_sleep 10) [] Tvoid));
    ("ros_subscribe_sensor",
       Gfun (External (EF_ros_subscribe "sensor" "In" queue) [tptr sensor_cb_type] Tvoid));
    ("ros_advertise_cmd", Gfun (External (EF_ros_advertise "cmd" "Out" 1) [] Tvoid));
    ("ros_publish_cmd", Gfun (External (EF_ros_publish "cmd" "Out") [tptr tOut] Tvoid));
    ("Controller_initialize",
       Gfun (External (EF_controller_initialize "Controller_U" "Controller_Y") [] Tvoid));
    ("Controller_step",
       Gfun (External (EF_controller_step "Controller_U" "Controller_Y") [] Tvoid));
    ("sensor_callback", fn Tvoid [("msg", tptr tIn)] [] [("t", tint)] (seq [
       Sset "t" (Efield (Ederef (Etempvar "msg" (tptr tIn)) tIn) "v" tint);
       Sassign (Efield (Evar "sensor_msg" tIn) "v" tint) (Etempvar "t" tint);
       Sreturn None]));
    ("input_glue", fn Tvoid [] [] [("t", tint)] (seq [
       Sset "t" (Efield (Evar "sensor_msg" tIn) "v" tint);
       Sassign (Efield (Evar "Controller_U" tU) "In1" tint) (Etempvar "t" tint);
       Sreturn None]));
    ("output_glue", fn Tvoid [("command", tptr tOut)] [] [("t", tint)] (seq [
       Sset "t" (Efield (Evar "Controller_Y" tY) "Out1" tint);
       Sassign (Efield (Ederef (Etempvar "command" (tptr tOut)) tOut) "cmd" tint) (Etempvar "t" tint);
       Sreturn None]));
    ("loop", fn Tvoid [] [] [("ok", tint)] (seq [
       Sloop (seq [
         Scall (Some "ok") (Evar "ros_ok" (Tfunction [] tint)) [];
         Sifthenelse (Etempvar "ok" tint) Sskip Sbreak;
         call0 "ros_spinOnce";
         call0 "input_glue";
         call0 "Controller_step";
         Scall None (Evar "output_glue" (Tfunction [tptr tOut] Tvoid))
               [Eaddrof (Evar "cmd_msg" tOut) (tptr tOut)];
         Scall None (Evar "ros_publish_cmd" (Tfunction [tptr tOut] Tvoid))
               [Eaddrof (Evar "cmd_msg" tOut) (tptr tOut)];
         call0 "ros_rate_sleep"]);
       Sreturn None]));
    ("main", fn tint [] [] [] (seq [
       call0 "ros_init";
       call0 "Controller_initialize";
       Scall None (Evar "ros_subscribe_sensor" (Tfunction [tptr sensor_cb_type] Tvoid))
             [Eaddrof (Evar "sensor_callback" sensor_cb_type) (tptr sensor_cb_type)];
       call0 "ros_advertise_cmd";
       call0 "loop";
       ret0]))];
  prog_main := "main" |}.

(** The controller counts its steps and outputs [In1 + steps so far]. *)
Definition int_field (mv : mval) (f : ident) : Z :=
  match mv with
  | MVstruct fs =>
      match find_assoc f fs with
      | Some (MVscalar (Vint n)) => n
      | _ => 0
      end
  | _ => 0
  end.

Definition counter_step (s : Z) (u : mval) : Z * mval :=
  (s + 1, MVstruct [("Out1", sc (Vint (int_field u "In1" + s)))]).

Definition msg_In (v : Z) : mval := MVstruct [("v", sc (Vint v))].

(** Spin 0: one message (5); spin 1: three messages (6, 7, 8) and one on
    a topic nobody subscribed to; spin 2: nothing. *)
Definition arrivals (k : nat) : list arrival :=
  match k with
  | O => [mkarrival "sensor" (msg_In 5) 10]
  | 1%nat => [mkarrival "sensor" (msg_In 6) 11; mkarrival "other" (msg_In 100) 12;
              mkarrival "sensor" (msg_In 7) 13; mkarrival "sensor" (msg_In 8) 14]
  | _ => []
  end.

(** The ROS time of cycle [k]. *)
Definition clock (k : nat) : Z := 100 * Z.of_nat k.

Definition node_ctx : ros_context Z := mkctx arrivals clock 0 counter_step Ros1.

Definition U (in1 : Z) : mval := MVstruct [("In1", sc (Vint in1)); ("In2", sc (Vint 0))].
Definition Y (out1 : Z) : mval := MVstruct [("Out1", sc (Vint out1))].
Definition Out (cmd : Z) : mval := MVstruct [("cmd", sc (Vint cmd))].

(** Before the loop: the controller's initialisation, the subscription
    (with its queue size) and the advertisement. *)
Definition node_start (queue : nat) : trace :=
  [Einit; Esubscribe "sensor" "In" queue; Eadvertise "cmd" "Out" 1].

(** Three cycles; in the second, the newest message (8) is the one the
    controller sees; in the third, it is still 8. *)
Definition node_cycles : trace :=
  [Estep (U 5) (Y 5); Epublish "cmd" (Out 5); Esleep 10;
   Estep (U 8) (Y 9); Epublish "cmd" (Out 9); Esleep 10;
   Estep (U 8) (Y 10); Epublish "cmd" (Out 10); Esleep 10].

Example node_run: run_trace 1000 (node 1) node_ctx 3 = Some (node_start 1 ++ node_cycles)%list.
Proof. vm_compute. reflexivity. Qed.

(** With a larger queue the callback runs for each of 6, 7, 8: the
    cycles are the same, since the last one wins; the subscription shows
    the queue size. *)
Example node_run_queue3: run_trace 1000 (node 3) node_ctx 3 = Some (node_start 3 ++ node_cycles)%list.
Proof. vm_compute. reflexivity. Qed.

Example node_run_0: run_trace 1000 (node 1) node_ctx 0 = Some (node_start 1).
Proof. vm_compute. reflexivity. Qed.

(** Without [Controller_initialize()] in [main], the controller has no
    state: its first step is undefined (no result), and a run without
    cycles shows no [Einit]. *)
Definition drop_init (s : statement) : statement :=
  match s with
  | Ssequence i (Ssequence _ rest) => Ssequence i rest
  | _ => s
  end.

Definition node_no_init : program :=
  {| prog_types := prog_types (node 1);
     prog_defs := map (fun d => match d with
                                | ("main", Gfun (Internal f)) =>
                                    ("main", Gfun (Internal (mkfunction (fn_return f) (fn_params f)
                                      (fn_vars f) (fn_temps f) (drop_init (fn_body f)))))
                                | _ => d
                                end) (prog_defs (node 1));
     prog_main := "main" |}.

Example node_no_init_stuck: run_trace 1000 node_no_init node_ctx 1 = None.
Proof. vm_compute. reflexivity. Qed.

Example node_no_init_0:
  run_trace 1000 node_no_init node_ctx 0 = Some [Esubscribe "sensor" "In" 1; Eadvertise "cmd" "Out" 1].
Proof. vm_compute. reflexivity. Qed.

(** A controller whose output does not have the type of [Controller_Y]
    makes the step undefined. *)
Definition bad_ctx : ros_context unit :=
  mkctx arrivals clock tt (fun s u => (s, MVstruct [("Out1", sc (Vlong 1))])) Ros1.

Example node_bad_controller: run_trace 1000 (node 1) bad_ctx 3 = None.
Proof. vm_compute. reflexivity. Qed.

(** ** Queues: which messages [ros_spinOnce] delivers *)

Definition sub_q (q : nat) (cb : ident) : subscription := mksub "sensor" "In" q cb.

Example deliverable_queue1:
  deliverable [sub_q 1 "cb"] (arrivals 1) = [(sub_q 1 "cb", mkarrival "sensor" (msg_In 8) 14)].
Proof. vm_compute. reflexivity. Qed.

Example deliverable_queue2:
  deliverable [sub_q 2 "cb"] (arrivals 1) = [(sub_q 2 "cb", mkarrival "sensor" (msg_In 7) 13); (sub_q 2 "cb", mkarrival "sensor" (msg_In 8) 14)].
Proof. vm_compute. reflexivity. Qed.

(** Queue size 0 is unbounded; two subscriptions each get their copy, in
    arrival order. *)
Example deliverable_two_subs:
  deliverable [sub_q 0 "a"; sub_q 1 "b"] (arrivals 1)
  = [(sub_q 0 "a", mkarrival "sensor" (msg_In 6) 11); (sub_q 0 "a", mkarrival "sensor" (msg_In 7) 13);
     (sub_q 0 "a", mkarrival "sensor" (msg_In 8) 14); (sub_q 1 "b", mkarrival "sensor" (msg_In 8) 14)].
Proof. vm_compute. reflexivity. Qed.

(** An echo node whose callback republishes every message it receives,
    with queue size 2: the trace shows exactly the delivered messages. *)
Definition echo (queue : nat) : program := {|
  prog_types := [Composite "In" [("v", tint)]];
  prog_defs := [
    ("ros_ok", Gfun (External EF_ros_ok [] tint));
    ("ros_spinOnce", Gfun (External EF_ros_spinOnce [] Tvoid));
    ("ros_rate_sleep", Gfun (External (EF_ros_rate_sleep 10) [] Tvoid));
    ("ros_subscribe_sensor",
       Gfun (External (EF_ros_subscribe "sensor" "In" queue) [tptr sensor_cb_type] Tvoid));
    ("ros_advertise_echo", Gfun (External (EF_ros_advertise "echo" "In" 1) [] Tvoid));
    ("ros_publish_echo", Gfun (External (EF_ros_publish "echo" "In") [tptr tIn] Tvoid));
    ("echo_callback", fn Tvoid [("msg", tptr tIn)] [] [] (seq [
       Scall None (Evar "ros_publish_echo" (Tfunction [tptr tIn] Tvoid)) [Etempvar "msg" (tptr tIn)];
       Sreturn None]));
    ("main", fn tint [] [] [("ok", tint)] (seq [
       Scall None (Evar "ros_subscribe_sensor" (Tfunction [tptr sensor_cb_type] Tvoid))
             [Eaddrof (Evar "echo_callback" sensor_cb_type) (tptr sensor_cb_type)];
       call0 "ros_advertise_echo";
       Sloop (seq [
         Scall (Some "ok") (Evar "ros_ok" (Tfunction [] tint)) [];
         Sifthenelse (Etempvar "ok" tint) Sskip Sbreak;
         call0 "ros_spinOnce";
         call0 "ros_rate_sleep"]);
       ret0]))];
  prog_main := "main" |}.

Example echo_run:
  run_trace 1000 (echo 2) node_ctx 3
  = Some [Esubscribe "sensor" "In" 2; Eadvertise "echo" "In" 1;
          Epublish "echo" (msg_In 5); Esleep 10;
          Epublish "echo" (msg_In 7); Epublish "echo" (msg_In 8); Esleep 10;
          Esleep 10].
Proof. vm_compute. reflexivity. Qed.

(** ** Time: what [ros_now] answers *)

(** A node whose callback stores [ros_now()] (the receipt time of the
    message it is called for) into [t_recv], and whose loop publishes, in
    each cycle, [t_recv] and [ros_now()] read after [ros_spinOnce] (the
    cycle's time). *)
Definition tU64 : type := Tlong Unsigned.
Definition tTimes : type := Tstruct "Times".
Definition clock_node : program := {|
  prog_types := [Composite "In" [("v", tint)]; Composite "Times" [("recv", tU64); ("now", tU64)]];
  prog_defs := [
    ("ros_ok", Gfun (External EF_ros_ok [] tint));
    ("ros_now", Gfun (External EF_ros_now [] tU64));
    ("ros_spinOnce", Gfun (External EF_ros_spinOnce [] Tvoid));
    ("ros_rate_sleep", Gfun (External (EF_ros_rate_sleep 10) [] Tvoid));
    ("ros_subscribe_sensor",
       Gfun (External (EF_ros_subscribe "sensor" "In" 0) [tptr sensor_cb_type] Tvoid));
    ("ros_advertise_times", Gfun (External (EF_ros_advertise "times" "Times" 1) [] Tvoid));
    ("ros_publish_times", Gfun (External (EF_ros_publish "times" "Times") [tptr tTimes] Tvoid));
    ("t_recv", Gvar tU64);
    ("out", Gvar tTimes);
    ("cb", fn Tvoid [("msg", tptr tIn)] [] [("t", tU64)] (seq [
       Scall (Some "t") (Evar "ros_now" (Tfunction [] tU64)) [];
       Sassign (Evar "t_recv" tU64) (Etempvar "t" tU64);
       Sreturn None]));
    ("main", fn tint [] [] [("ok", tint); ("t", tU64)] (seq [
       Scall None (Evar "ros_subscribe_sensor" (Tfunction [tptr sensor_cb_type] Tvoid))
             [Eaddrof (Evar "cb" sensor_cb_type) (tptr sensor_cb_type)];
       call0 "ros_advertise_times";
       Sloop (seq [
         Scall (Some "ok") (Evar "ros_ok" (Tfunction [] tint)) [];
         Sifthenelse (Etempvar "ok" tint) Sskip Sbreak;
         call0 "ros_spinOnce";
         Scall (Some "t") (Evar "ros_now" (Tfunction [] tU64)) [];
         Sassign (Efield (Evar "out" tTimes) "now" tU64) (Etempvar "t" tU64);
         Sassign (Efield (Evar "out" tTimes) "recv" tU64) (Evar "t_recv" tU64);
         Scall None (Evar "ros_publish_times" (Tfunction [tptr tTimes] Tvoid))
               [Eaddrof (Evar "out" tTimes) (tptr tTimes)];
         call0 "ros_rate_sleep"]);
       ret0]))];
  prog_main := "main" |}.

Definition times (recv now : Z) : mval :=
  MVstruct [("recv", sc (Vlong recv)); ("now", sc (Vlong now))].

(** Cycle 0: the message of spin 0 was received at 10, the cycle's time
    is [clock 1 = 100]; cycle 1: the last of the four messages of spin 1
    was received at 14 (the one on "other" is not delivered, so its
    time 12 is never seen), the cycle's time is 200; cycle 2: nothing
    arrives, [t_recv] keeps 14, the time is 300. *)
Example clock_run:
  run_trace 1000 clock_node node_ctx 3
  = Some [Esubscribe "sensor" "In" 0; Eadvertise "times" "Times" 1;
          Epublish "times" (times 10 100); Esleep 10;
          Epublish "times" (times 14 200); Esleep 10;
          Epublish "times" (times 14 300); Esleep 10].
Proof. vm_compute. reflexivity. Qed.

Example clock_wt: check_program clock_node = true.
Proof. vm_compute. reflexivity. Qed.

(** ** Typing *)

(** The example programs written as the generator writes them are well
    typed. *)
Example node_wt: check_program (node 1) = true.
Proof. vm_compute. reflexivity. Qed.

Lemma node_wt_prop: wt_program (node 1).
Proof. apply check_program_correct. vm_compute. reflexivity. Qed.

Example copy_wt: check_program prog_copy = true.
Proof. vm_compute. reflexivity. Qed.

Example array_wt: check_program (prog_array 0) = true.
Proof. vm_compute. reflexivity. Qed.

Example echo_wt: check_program (echo 2) = true.
Proof. vm_compute. reflexivity. Qed.

(** [prog_wrap] relies on implicit conversions ([return a] of an [int] in
    an [unsigned char] function is fine, but [r = a] assigns an [int] to
    an [unsigned short]): the checker, which wants equal types in
    assignments, rejects it. *)
Example wrap_not_wt: check_program prog_wrap = false.
Proof. vm_compute. reflexivity. Qed.

(** Ill-typed variants of the node are rejected. *)
Definition map_defs (f : ident * globdef -> ident * globdef) (p : program) : program :=
  {| prog_types := prog_types p; prog_defs := map f (prog_defs p); prog_main := prog_main p |}.

(** a field read at the wrong type *)
Definition node_bad_field : program :=
  map_defs (fun d => if string_dec (fst d) "input_glue"
                     then ("input_glue", fn Tvoid [] [] [("t", tint)] (seq [
                             Sset "t" (Efield (Evar "sensor_msg" tIn) "v" tuint);
                             Sreturn None]))
                     else d) (node 1).
Example node_bad_field_rejected: check_program node_bad_field = false.
Proof. vm_compute. reflexivity. Qed.

(** an undeclared temporary *)
Definition node_bad_temp : program :=
  map_defs (fun d => if string_dec (fst d) "input_glue"
                     then ("input_glue", fn Tvoid [] [] [] (seq [
                             Sset "t" (Efield (Evar "sensor_msg" tIn) "v" tint);
                             Sreturn None]))
                     else d) (node 1).
Example node_bad_temp_rejected: check_program node_bad_temp = false.
Proof. vm_compute. reflexivity. Qed.

(** a publisher declared with the wrong signature *)
Definition node_bad_extern : program :=
  map_defs (fun d => if string_dec (fst d) "ros_publish_cmd"
                     then ("ros_publish_cmd", Gfun (External (EF_ros_publish "cmd" "Out") [tptr tIn] Tvoid))
                     else d) (node 1).
Example node_bad_extern_rejected: check_program node_bad_extern = false.
Proof. vm_compute. reflexivity. Qed.

(** a local that hides a global *)
Definition node_bad_shadow : program :=
  map_defs (fun d => if string_dec (fst d) "input_glue"
                     then ("input_glue", fn Tvoid [] [] [("sensor_msg", tint)] (Sreturn None))
                     else d) (node 1).
Example node_bad_shadow_rejected: check_program node_bad_shadow = false.
Proof. vm_compute. reflexivity. Qed.

(** struct definitions out of order (a member of a struct defined later) *)
Example composites_order:
  composites_ok [] [comp_M; comp_A] = false /\ composites_ok [] [comp_A; comp_M] = true.
Proof. vm_compute. split; reflexivity. Qed.

(** ** The semantics, through T5 *)

(** The mini-node's run is a behaviour of the program in the sense of the
    big-step semantics. *)
Lemma node_behaves: program_behaves (node 1) node_ctx 3 (node_start 1 ++ node_cycles)%list.
Proof.
  apply run_trace_sound with (fuel := 1000%nat). vm_compute. reflexivity.
Qed.

(** And it is its only behaviour (determinism). *)
Lemma node_only_behaviour:
  forall t, program_behaves (node 1) node_ctx 3 t -> t = (node_start 1 ++ node_cycles)%list.
Proof.
  intros t B. apply (run_trace_exact Z node_ctx 1000 (node 1) 3); [vm_compute; reflexivity | exact B].
Qed.

(** A statement-level use of T5: the callback of the copy example, run
    from a memory holding a message, is a derivation of [eval_funcall]. *)
Definition copy_ge := globalenv prog_copy.
Definition copy_m0 := init_mem prog_copy.
Definition the_msg : mval :=
  MVstruct [("a", MVstruct [("b", sc (Vint 7)); ("c", sc (Vfloat pdouble))]); ("x", sc (Vint 1))].

Lemma copy_callback_runs:
  exists t m' w' v,
    eval_funcall quiet_ctx copy_ge (fst (alloc copy_m0 tM the_msg)) (initial_world quiet_ctx 0)
      (match find_funct copy_ge "cb" with Some fd => fd | None => Internal (mkfunction Tvoid [] [] [] Sskip) end)
      [Vptr (snd (alloc copy_m0 tM the_msg)) []] t m' w' v
    /\ read_global prog_copy m' "g_copy" = Some the_msg.
Proof.
  destruct (call_fuel quiet_ctx copy_ge 100 (fst (alloc copy_m0 tM the_msg)) (initial_world quiet_ctx 0)
      (match find_funct copy_ge "cb" with Some fd => fd | None => Internal (mkfunction Tvoid [] [] [] Sskip) end)
      [Vptr (snd (alloc copy_m0 tM the_msg)) []]) as [[[[t m'] w'] v]|] eqn:R.
  - exists t, m', w', v. split.
    + eapply call_fuel_sound; eauto.
    + vm_compute in R. inversion R. vm_compute. reflexivity.
  - vm_compute in R. discriminate R.
Qed.
