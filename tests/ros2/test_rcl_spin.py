"""The rcl wrapper's ``ros_spinOnce`` against the environment model's
``rcl_deliverable`` (DESIGN.md section 6.1, "The ROS 2 wrapper"): per
subscription in model order at most its queue size of the messages
available, in take order, one subscription's after the other's, each
callback run as its message is taken, ``ros_now()`` in a callback the
message's receipt time; after the spin, ``ros_now()`` the ROS clock read
at its first call and kept until the next spin.  A C harness includes the
node's own ``<node>_rcl.c`` and replaces ``rcl_take`` by a script (per
subscription, the messages available and their ``received_timestamp``);
its callbacks record what they receive and ``ros_now()``; the order is
compared with the model's, computed here, over random scripts, for three
subscriptions (queue sizes 1, 3 and 2) and for one (queue size 3)."""

from __future__ import annotations

import random
import subprocess

import pytest

from pyrosgen.proof.modeltext import parse_model_text
from pyrosgen.ros.wrapper import GLUE_CFLAGS
from pyrosgen.ros2.build import build_ros2, compile_flags, link_flags

QUEUES = {"three": (1, 3, 2), "one": (3,)}
CASES = 300


def model(queues: tuple[int, ...]) -> str:
    names = "ABC"[:len(queues)]
    topics = "".join(f"  - {{name: /in_{n.lower()}, direction: subscribe, type: std_msgs/Float64, queue_size: {q}}}\n"
                     for n, q in zip(names, queues))
    rels = "".join(f"    - {{topic: /in_{n.lower()}, field: data, input: {n}}}\n" for n in names)
    fields = ", ".join(f"{n}: float64" for n in names)
    return f"""\
node: {{name: spin{len(queues)}, period_ms: 20}}
controller:
  name: Echo
  inputs:
    name: Echo_U
    fields: {{{fields}}}
  outputs:
    name: Echo_Y
    fields: {{X: float64}}
  blocks: [{{name: unused, block: Constant, type: bool, value: false}}]   # a diagram has at least one block
  outports: {{X: A}}
topics:
{topics}  - {{name: /out, direction: publish, type: std_msgs/Float64, queue_size: 1}}
relations:
  inputs:
{rels}  outputs:
    - {{output: X, topic: /out, field: data}}
"""


def harness(node: str, subs: list[str]) -> str:
    """Reads cases from standard input (per subscription: a count, then that
    many receipt times), runs one ros_spinOnce() per case and prints, per
    callback run, ``subscription message ros_now``, then ``end``."""
    k = len(subs)
    which = " : ".join(f"s == &g_sub_{c} ? {i}" for i, c in enumerate(subs)) + " : -1"
    cbs = "".join(f"static void cb_{c}(struct std_msgs_Float64 *m) {{ seen({i}, m); }}\n" for i, c in enumerate(subs))
    setup = "".join(f"    g_sub_{c}_up = 1;\n    g_cb_{c} = cb_{c};\n    std_msgs__msg__Float64__init(&g_take_{c});\n"
                    for c in subs)
    return f"""#include "{node}_rcl.c"

static int avail[{k}], taken[{k}];
static long long at[{k}][16];

rcl_ret_t rcl_take(const rcl_subscription_t *s, void *msg, rmw_message_info_t *info,
                   rmw_subscription_allocation_t *allocation)
{{
    int i = {which};
    (void)allocation;
    if (i < 0) abort();
    if (taken[i] >= avail[i]) return RCL_RET_SUBSCRIPTION_TAKE_FAILED;
    ((std_msgs__msg__Float64 *)msg)->data = (double)(100 * i + taken[i]);
    info->received_timestamp = at[i][taken[i]];
    taken[i]++;
    return RCL_RET_OK;
}}

static void seen(int i, struct std_msgs_Float64 *m)
{{
    printf("%d %d %llu\\n", i, (int)m->data - 100 * i, ros_now());
}}

{cbs}
int main(void)
{{
{setup}    for (;;) {{
        for (int i = 0; i < {k}; ++i) {{
            if (scanf("%d", &avail[i]) != 1) return 0;
            taken[i] = 0;
            for (int j = 0; j < avail[i]; ++j)
                if (scanf("%lld", &at[i][j]) != 1) return 2;
        }}
        struct timespec t0, t1;
        clock_gettime(CLOCK_REALTIME, &t0);
        ros_spinOnce();
        unsigned long long n1 = ros_now(), n2 = ros_now();
        clock_gettime(CLOCK_REALTIME, &t1);
        unsigned long long lo = (unsigned long long)t0.tv_sec * 1000000000ULL + (unsigned long long)t0.tv_nsec;
        unsigned long long hi = (unsigned long long)t1.tv_sec * 1000000000ULL + (unsigned long long)t1.tv_nsec;
        /* the cycle's time: the system clock read after the spin, the same at the second call */
        printf("now %d %d\\n", lo <= n1 && n1 <= hi, n1 == n2);
        printf("end\\n");
        fflush(stdout);
    }}
}}
"""


def expected(queues, case) -> list[tuple[int, int, int]]:
    """The model: each subscription's first min(available, queue) messages
    (the fake's reader holds exactly what it offers), in take order, one
    subscription's after the other's."""
    return [(i, j, t) for i, (q, times) in enumerate(zip(queues, case)) for j, t in enumerate(times[:q])]


def cases(queues, rng: random.Random) -> list[list[list[int]]]:
    out = []
    for _ in range(CASES):
        base = rng.randrange(1, 1 << 62)
        spread = rng.choice([0, 2, 5, 1000])   # 0: every time equal
        out.append([[base + rng.randrange(spread + 1) for _ in range(rng.randrange(q + 3))] for q in queues])
    return out


@pytest.fixture(scope="module")
def built(ros2_install, ros2_nodes, tmp_path_factory):
    """Both nodes, built once: shape -> (build result, subscriptions' C names)."""
    out = {}
    for shape, queues in QUEUES.items():
        d = tmp_path_factory.mktemp(f"spin_{shape}")
        (d / "m.yaml").write_text(model(queues))
        res = build_ros2(d / "m.yaml", None, ros2_nodes / f"spin_{shape}", install=ros2_install)
        subs = [t.c_name for t in parse_model_text(res.generated.proved_model).topics if t.direction == "subscribe"]
        assert len(subs) == len(queues)
        out[shape] = (res, subs)
    return out


def run_spins(res, subs, queues, rcl_text: str, tmp_path, ros2_install):
    """The harness over the wrapper text ``rcl_text`` (the node's, or a
    mutant of it): per scripted spin, the deliveries, and the cycle's time
    line; and the script."""
    node = res.model.name
    (tmp_path / f"{node}_rcl.c").write_text(rcl_text)
    src, exe = tmp_path / "harness.c", tmp_path / "harness"
    src.write_text(harness(node, subs))
    cflags = [f for f in GLUE_CFLAGS if f not in ("-Werror", "-pedantic")]
    cc = subprocess.run(["gcc", *cflags, "-I", str(tmp_path), "-I", str(res.out_dir), *compile_flags(ros2_install),
                         str(src), "-o", str(exe), *link_flags(ros2_install, res.model), "-lm"],
                        capture_output=True, text=True)
    assert cc.returncode == 0, cc.stderr[-3000:]
    script = cases(queues, random.Random(31 + len(queues)))
    stdin = "".join(" ".join(str(x) for times in case for x in (len(times), *times)) + "\n" for case in script)
    run = subprocess.run([str(exe)], input=stdin, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr[-2000:]
    got, cur, nows = [], [], []
    for line in run.stdout.splitlines():
        if line == "end":
            got.append(cur)
            cur = []
        elif line.startswith("now "):
            nows.append(line)
        else:
            cur.append(tuple(int(x) for x in line.split()))
    assert len(got) == CASES
    return script, got, nows


@pytest.mark.parametrize("shape", sorted(QUEUES))
def test_spin_once_delivers_as_rcl_deliverable(shape, built, ros2_install, tmp_path):
    res, subs = built[shape]
    queues = QUEUES[shape]
    text = (res.out_dir / f"{res.model.name}_rcl.c").read_text()
    script, got, nows = run_spins(res, subs, queues, text, tmp_path, ros2_install)
    assert nows == ["now 1 1"] * CASES
    unsorted = 0
    for case, delivered in zip(script, got):
        want = expected(queues, case)
        assert delivered == want, f"script {case}: delivered {delivered}, the model {want}"
        unsorted += [t for _, _, t in want] != sorted(t for _, _, t in want)
    # the scripts did exercise spins whose order is not the receipt times' (a
    # merge or a sort on the times would fail them)
    assert unsorted > CASES // 10


#: Wrapper mutants, each a departure from rcl_deliverable or from ros_now's
#: meaning that the harness above must see: (old, new, count of old).
MUTANTS = {
    # ros_now() in a callback answers the cycle's time, not the receipt time
    "receipt-time-not-set": ("        g_now_state = 2;\n", "", None),
    # a history depth off by one: one more message taken than the queue holds
    "depth-plus-one": ("taken < ", "taken <= ", None),
    # after the spin, ros_now() answers the last receipt time, not the clock
    "cycle-time-not-read": ("    g_now_state = 0;   /* the ROS time of the cycle", "    /* the ROS time of the cycle", 1),
    # a history depth off by one the other way (the queue of 3 taken as 2)
    "depth-minus-one": ("taken < 3; ++taken)", "taken < 2; ++taken)", 1),
}


@pytest.mark.parametrize("mutant", sorted(MUTANTS))
def test_wrapper_mutants_are_caught(mutant, built, ros2_install, tmp_path):
    res, subs = built["three"]
    queues = QUEUES["three"]
    text = (res.out_dir / f"{res.model.name}_rcl.c").read_text()
    old, new, count = MUTANTS[mutant]
    assert text.count(old) == (count or len(subs)), mutant
    script, got, nows = run_spins(res, subs, queues, text.replace(old, new), tmp_path, ros2_install)
    wrong = sum(delivered != expected(queues, case) for case, delivered in zip(script, got))
    wrong += sum(line != "now 1 1" for line in nows)
    assert wrong > 0, f"the mutant {mutant} delivers as the model says"
