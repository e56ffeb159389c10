# Two commands do all the set-up: `make demo` and `make test`.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
DEMO_TMP := build/demo
# A demo step meant to report something: says so before it runs, fails the demo on any other exit code.
STEP := $(BIN)/python tools/demo_step.py

.PHONY: demo test check docs bench clean ecosystem ecosystem-update

$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet --config-settings editable_mode=compat -e '.[all,dev]'
	touch $(STAMP)

demo: $(STAMP)
	@rm -rf $(DEMO_TMP) && mkdir -p $(DEMO_TMP)
	@echo "== armtool lint on a clean arm (URDF + SRDF + kinematics.yaml): expect no findings"
	$(BIN)/armtool lint fixtures/robots/clean_arm/urdf fixtures/robots/clean_arm/config
	@echo
	@echo "== armtool lint on a broken arm and a broken MoveIt config"
	@$(STEP) 1 "errors and warnings in the URDF, SRDF and kinematics.yaml" -- \
	  $(BIN)/armtool lint fixtures/robots/broken_arm fixtures/robots/clean_arm/config_broken
	@echo
	@echo "== armtool lint on a xacro arm: findings point into the .xacro sources"
	@$(STEP) 0 "2 warnings located in the xacro macro file; warnings do not fail lint" -- \
	  $(BIN)/armtool lint fixtures/robots/xacro_arm
	@echo
	@echo "== armtool rules U301"
	$(BIN)/armtool rules U301
	@echo
	@echo "== armtool ik-bench on the clean arm: every built-in solver, 200 targets, TRAC-IK protocol"
	$(BIN)/armtool ik-bench fixtures/robots/clean_arm/urdf/clean_arm.urdf --base base_link --tip tool0 --samples 200
	@echo
	@echo "== armtool calibrate: render 40 AprilTag images of the clean arm with hidden kinematic errors (2 bad samples mixed in), then fit them"
	@set -e; d=$$(mktemp -d); trap 'rm -rf $$d' EXIT; \
	$(BIN)/armtool calibrate simulate fixtures/robots/clean_arm/urdf/clean_arm.urdf --flange tool0 -o $$d/dataset --samples 40 --bad-samples 2; \
	$(BIN)/armtool calibrate check $$d/dataset; \
	$(BIN)/armtool calibrate fit $$d/dataset --out $$d/out --holdout 0.25; \
	echo "-- calibrated.urdf differs from the nominal one only in joint origins:"; \
	$(STEP) 1 "differences; diff exits 1 when files differ" --head 8 -- \
	  diff fixtures/robots/clean_arm/urdf/clean_arm.urdf $$d/out/calibrated.urdf
	@echo
	@echo "== armtool servo-sim + armtool limits --mode auto: find the stops of a simulated 5-joint AX-12A arm, write limits YAML and URDF limits"
	@set -e; d=$$(mktemp -d); \
	$(BIN)/armtool servo-sim fixtures/servo/ax12_arm.yaml --duration 120 --port-file $$d/port > /dev/null & sim=$$!; \
	trap 'kill $$sim 2>/dev/null || true; rm -rf $$d' EXIT; \
	for i in $$(seq 100); do test -s $$d/port && break; sleep 0.1; done; \
	$(BIN)/armtool limits --port $$(cat $$d/port) --arm fixtures/servo/ax12_arm.yaml --mode auto --yes --speed 120 \
	  -o $$d/ax12_limits.yaml --urdf fixtures/servo/ax12_arm.urdf --urdf-out $$d/ax12_arm.limited.urdf; \
	echo "-- limits YAML (first joint):"; sed -n '1,27p' $$d/ax12_limits.yaml; \
	echo "-- armtool lint on the URDF with the measured limits:"; $(BIN)/armtool lint $$d/ax12_arm.limited.urdf
	@echo
	@echo "== armtool servo-lut fit/export/apply on a bundled measurement file"
	@echo "   (fixtures/servo/lut/ax12a_meas.csv: generated from the simulator's AX-12A potentiometer model by"
	@echo "    fixtures/servo/lut/make_fixtures.py, not measured on a real servo)"
	$(BIN)/armtool servo-lut fit fixtures/servo/lut/ax12a_meas.csv -o $(DEMO_TMP)/lut.json
	$(BIN)/armtool servo-lut export $(DEMO_TMP)/lut.json --format c --name shoulder_lut -o $(DEMO_TMP)/shoulder_lut.h
	head -n 30 $(DEMO_TMP)/shoulder_lut.h
	$(BIN)/armtool servo-lut apply $(DEMO_TMP)/lut.json --angles 45,150,255
	@echo
	@echo "== armtool servo-lut on the simulated AX-12A arm: limits, measure with the encoder, fit, check against --max-err 0.5 deg (it would exit 1 above it)"
	@set -e; d=$(DEMO_TMP)/sim; mkdir -p $$d; : > $$d/ports; \
	$(BIN)/armtool servo-sim fixtures/servo/ax12_arm.yaml --duration 120 > $$d/ports & sim=$$!; \
	trap 'kill $$sim 2>/dev/null || true' EXIT; \
	for i in $$(seq 50); do [ "$$(wc -l < $$d/ports)" -ge 2 ] && break; sleep 0.1; done; \
	port=$$(sed -n 1p $$d/ports); enc=encoder:$$(sed -n 2p $$d/ports); \
	$(BIN)/armtool limits --port $$port --mode auto --ids 1 --model AX-12A --speed 120 --yes -o $$d/limits.yaml; \
	$(BIN)/armtool servo-lut measure --port $$port --id 1 --reference $$enc --limits $$d/limits.yaml --points 41 --speed 300 --dwell 0.02 --yes -o $$d/meas.csv; \
	$(BIN)/armtool servo-lut fit $$d/meas.csv -o $$d/lut.json; \
	$(BIN)/armtool servo-lut check $$d/lut.json --port $$port --id 1 --reference $$enc --limits $$d/limits.yaml --n 15 --speed 300 --dwell 0.02 --max-err 0.5 --yes
	@echo
	@echo "== armtool traj: the MoveIt lecture's three exercises on the clean arm, without ROS"
	@echo "   (acceleration limits from fixtures/traj/clean_arm_joint_limits.yaml; a URDF has none)"
	@set -e; d=$(DEMO_TMP)/traj; mkdir -p $$d; U=fixtures/robots/clean_arm/urdf/clean_arm.urdf; JL=fixtures/traj/clean_arm_joint_limits.yaml; \
	echo "-- 1. circle of radius 0.1 m in the y-z plane through the tool's start position, IK point by point"; \
	$(BIN)/armtool traj cartesian $$U --base base_link --tip tool0 --start 0,-0.6,1.2,0,0.9,0 \
	  --center-offset 0,-0.1,0 --normal 1,0,0 --eef-step 0.005 -o $$d/circle.csv; \
	$(BIN)/armtool traj time $$d/circle.csv --urdf $$U --joint-limits $$JL -o $$d/circle_timed.csv; \
	echo "-- 2. drop every 4th point (first and last kept), re-time, then play it at a quarter of the speed"; \
	$(BIN)/armtool traj thin $$d/circle.csv --every 4 --urdf $$U --joint-limits $$JL -o $$d/circle_thin.csv; \
	$(BIN)/armtool traj retime $$d/circle_thin.csv --scale 0.25 --urdf $$U --joint-limits $$JL -o $$d/circle_slow.yaml; \
	echo "-- 3. a second plan (a 10 cm line down from where the circle ends), joined to the first and re-timed as one"; \
	$(BIN)/armtool traj cartesian $$U --base base_link --tip tool0 --start $$(tail -n 1 $$d/circle.csv) \
	  --line 0,0,-0.1 --relative -o $$d/line.csv; \
	$(BIN)/armtool traj join $$d/circle.csv $$d/line.csv --urdf $$U --joint-limits $$JL -o $$d/joined.csv; \
	echo "-- traj check on every timed result (exit 0: no finding), and a plot"; \
	for f in circle_timed.csv circle_thin.csv circle_slow.yaml joined.csv; do \
	  $(BIN)/armtool traj check $$d/$$f --urdf $$U --joint-limits $$JL; done; \
	$(BIN)/armtool traj plot $$d/joined.csv --urdf $$U --joint-limits $$JL --base base_link --tip tool0 -o $$d/joined.png; \
	echo "-- a trajectory that is too fast: traj check names the point, time and joint"; \
	$(BIN)/armtool traj retime $$d/joined.csv --scale 1.5 -o $$d/too_fast.csv; \
	$(STEP) 1 "findings, the limits it exceeds; its last 4 lines shown" --tail 4 -- \
	  $(BIN)/armtool traj check $$d/too_fast.csv --urdf $$U --joint-limits $$JL
	@echo
	@echo "== make demo: every step behaved as expected (the steps marked 'expect ...' reported what they announced, with its exit code)"

test: $(STAMP)
	$(BIN)/python -m pytest -q

# The ecosystem check: armtool lint on every case of ../shared/realworld, compared with the
# committed baseline (tests/ecosystem/baseline.json); also run by `make test` (tests/test_ecosystem.py).
ecosystem: $(STAMP)
	$(BIN)/python tools/ecosystem.py

ecosystem-update: $(STAMP)
	$(BIN)/python tools/ecosystem.py --update

check: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/python -m mypy armtool

docs: $(STAMP)
	$(BIN)/python -m mkdocs build --strict --site-dir build/site
	@echo "the manual is in build/site/index.html (python tools/docs_examples.py refreshes its shown output)"

bench: $(STAMP)
	$(BIN)/python benchmarks/lint_bench.py
	-$(BIN)/python benchmarks/install_bench.py
	$(BIN)/python benchmarks/apriltag_bench.py
	$(BIN)/python benchmarks/calib_bench.py
	$(BIN)/python benchmarks/servo_lut_bench.py
	$(BIN)/python -m pip install --quiet --config-settings editable_mode=compat -e '.[all,dev,peers]'
	$(BIN)/python benchmarks/ik_bench.py
	$(BIN)/python benchmarks/traj_bench.py

clean:
	rm -rf $(VENV) build *.egg-info
