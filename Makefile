# pyrosgen: `make demo` (main job), `make test` (whole suite).
# Both set up what is missing first (Debian packages, the virtual environment,
# the Coq library) and are idempotent.

SHELL := /bin/bash
VENV  := .venv
PY    := $(VENV)/bin/python
PYTEST_ARGS ?=

.PHONY: all deps apt venv proofs demo test mutants clean distclean

all: test

## deps: Debian packages (only the missing ones), the virtual environment, the
## ROS 2 wheels (.venv-ros2) and the bash completion script (README "Installing": how to enable it)
COMPLETION := $(VENV)/share/bash-completion/completions/pyrosgen
deps: apt venv ros2-deps $(COMPLETION)

# generated from the command line's argument parser (pyrosgen/completion.py)
$(COMPLETION): pyrosgen/cli.py pyrosgen/completion.py $(VENV)/.installed
	@mkdir -p $(dir $@)
	@$(PY) -m pyrosgen completion > $@.tmp && mv $@.tmp $@

## ros2-deps: the pinned ROS 2 Kilted wheels (requirements-ros2.txt) in .venv-ros2, only when missing
.PHONY: ros2-deps
ros2-deps:
	@scripts/ros2-deps.sh

# VIEWERS=1: rviz too (scripts/deps.sh)
VIEWERS ?= 0
apt:
	@VIEWERS=$(VIEWERS) scripts/deps.sh

# The venv is made from Debian's interpreter with --system-site-packages so that
# Debian's rospy and message modules are importable from it.
venv: $(VENV)/.installed

$(VENV)/.installed: pyproject.toml | apt
	@test -x $(PY) || /usr/bin/python3 -m venv --system-site-packages $(VENV)
	@echo "deps: installing pyrosgen and its test extras into $(VENV)"
	@PIP_ROOT_USER_ACTION=ignore $(PY) -m pip install -q --disable-pip-version-check --no-warn-script-location -e '.[test]'
	@touch $@

## proofs: the Coq library, coqchk, and the no-admit check
proofs: apt
	@$(MAKE) --no-print-directory -C coq

## demo: the main job on the LandShark example (DIAGRAM=1: its controller as a proved block diagram),
## then the velocity guard's timeouts (rule 4.12) when its command sources fall silent,
## then the three-node system chain (DESIGN.md section 10) on a real master
demo: deps proofs
	@if [ "$(ROS)" = 2 ]; then scripts/demo-ros2.sh; else scripts/demo.sh; fi

## demo-ros2 (or demo ROS=2): the LandShark node built for ROS 2 (--ros2: rcl, Fast DDS on the loopback) against a simulated robot, then the three-node system
.PHONY: demo-ros2
demo-ros2: deps proofs
	@scripts/demo-ros2.sh

## docs: HTML documentation of the Coq library (coqdoc) and its front page, in build/docs/
.PHONY: docs
docs: venv
	@$(MAKE) --no-print-directory -C coq docs PYTHON=$(abspath $(PY)) DOCDIR=$(abspath build/docs)

## bench: the benchmarks of BENCHMARKS.md, ROS 2 (bench/ros2.py) included (rewrites its tables, plots in bench/results/);
## `make bench BENCH_ARGS=--quick` for a short run
.PHONY: bench
BENCH_ARGS ?=
bench: deps proofs
	@$(PY) bench/run.py $(BENCH_ARGS)

## mutants: the mutation catalogue, run on its own: the generator mutations that
## T2 refutes (coq/tests/Mutants.v, MutantsOrder.v, Stamps.v, Freshness.v, Strings.v, Sequences.v, ControllerArrays.v, ElemSequences.v), those of the
## controller that T6 and T8 refute (MutantsDiagram.v, Linked.v), the system wirings link_ok refuses and whose semantic property a run refutes (SystemMutants.v), the ROS 2 deliveries refuted (MutantsRos2.v), the ROS 2 stamps' mutants T2 refutes (MutantsStampRos2.v), the tamperings of the per-node .v refused by
## the model comparison, the wrapper mutations refused by the wrapper check, the
## output-folder tamperings refused by `pyrosgen verify`, a consistent error of the C printer
## refused by the printer validation (tests/validation/test_printer_mutation.py)
.PHONY: mutants
mutants: deps proofs
	@for f in coq/tests/LandShark.v coq/tests/Mutants.v coq/tests/MutantsOrder.v coq/tests/Stamps.v coq/tests/Freshness.v coq/tests/Strings.v coq/tests/Sequences.v coq/tests/ControllerArrays.v coq/tests/ElemSequences.v coq/tests/MutantsDiagram.v coq/tests/Linked.v coq/tests/SystemMutants.v coq/tests/MutantsRos2.v coq/tests/MutantsStampRos2.v; do (cd coq && coqc -R theories ROSGen -R tests ROSGenTests $${f#coq/}) || exit 1; done
	@echo "mutants: $$(cat coq/tests/Mutants.v coq/tests/MutantsOrder.v coq/tests/Stamps.v coq/tests/Freshness.v coq/tests/Strings.v coq/tests/Sequences.v coq/tests/ControllerArrays.v coq/tests/ElemSequences.v | grep -c '^Theorem [a-z_]*_refuted') generator mutations refuted by T2 (coq/tests/Mutants.v, coq/tests/MutantsOrder.v, coq/tests/Stamps.v, coq/tests/Freshness.v, coq/tests/Strings.v, coq/tests/Sequences.v, coq/tests/ControllerArrays.v, coq/tests/ElemSequences.v)"
	@echo "mutants: $$(grep -c '^Theorem [a-z_]*_refuted' coq/tests/MutantsDiagram.v) controller generator mutations refuted by T6 (coq/tests/MutantsDiagram.v)"
	@echo "mutants: $$(grep -c '^Theorem [a-z0-9_]*_refuted' coq/tests/Linked.v) controller mutations of the linked program refuted by T8 (coq/tests/Linked.v)"
	@echo "mutants: $$(grep '^Theorem [a-z0-9_]*_refuted' coq/tests/SystemMutants.v | grep -vc '_run_refuted') system wiring mutations refused by System.link_ok (coq/tests/SystemMutants.v)"
	@echo "mutants: $$(grep -c '^Theorem [a-z0-9_]*_run_refuted' coq/tests/SystemMutants.v) system wiring mutations refuted on a run of the nodes' programs (coq/tests/SystemMutants.v)"
	@echo "mutants: $$(grep -c '^Theorem [a-z_]*_refuted' coq/tests/MutantsRos2.v) ROS 2 delivery mutations refuted (coq/tests/MutantsRos2.v: against the delivery property T2's proof needs, the depth bound, and T2 itself)"
	@echo "mutants: $$(grep -c '^Theorem [a-z0-9_]*_refuted' coq/tests/MutantsStampRos2.v) ROS 2 stamp mutations refuted by T2 (coq/tests/MutantsStampRos2.v: seconds and nanoseconds swapped, the int32 seconds saturated instead of wrapped)"
	@$(PY) -m pytest -q -p no:cacheprovider tests/generate/test_seam.py tests/build/test_wrapper_check.py tests/build/test_elem_seq_wrapper_check.py tests/generate/test_verify.py tests/generate/test_verify_hostile.py tests/validation/test_printer_mutation.py tests/nversion/test_misreading.py tests/build/test_verify_package.py tests/build/test_verify_custom_msgs.py tests/build/test_build_flags.py tests/build/test_rebuild.py

## test: everything, in PYTEST_JOBS processes (pytest-xdist; a test file
## stays in one process, so its module fixtures are built once)
PYTEST_JOBS ?= 2
test: deps proofs
	@$(PY) -m pytest -n $(PYTEST_JOBS) --dist loadfile $(PYTEST_ARGS)

clean:
	@$(MAKE) --no-print-directory -C coq clean
	rm -rf build .pytest_cache

distclean: clean
	rm -rf $(VENV)
