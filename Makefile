# One-command entry points (see README "Quick start").
#   make sim    install what is missing, build, run the simulated system
#   make test   install what is missing, build, run every test, print "N passed, N failed"
#   make test-unit  build and run the gtests only (the cores; about a minute once built)
#   make soak   DURATION (600) s of exploring the room scene: no collision, distance, area and the
#               manager's resident memory printed, memory flat after the first minutes; a progress
#               line every minute; the map of the run with the robot's path in SOAK_PNG (catkin_ws/soak_map.png)
#   make soak-cover  COVER_DURATION (1800) s of cleaning (behaviour cover) in COVER_SCENE (cover_lounge),
#               seed SEED (3): no collision in any direction, best coverage_progress at least
#               COVER_MIN_PROGRESS (0.6; 30 min in the lounge gave 0.875), the manager's resident memory
#               flat over the second half of the run (sampled every minute), coverage_progress each minute,
#               the true floor covered at 10 minute steps (scripts/cover_truth.py); the map in $ROS_HOME (/tmp)
#   make fuzz   build the libFuzzer targets (fuzz/) and run each FUZZ_SECONDS (30) s; fails on a finding
#   make test-asan  every gtest built with AddressSanitizer + UndefinedBehaviorSanitizer and run
# Catkin and the ROS tools need Debian's /usr/bin/python3, not a pyenv shim that may shadow it.
SHELL := /bin/bash
ROOT  := $(abspath $(dir $(lastword $(MAKEFILE_LIST))))
WS    := $(ROOT)/catkin_ws
JOBS  ?= $(shell nproc)
BUILD_TYPE ?= Release
FUZZ_SECONDS ?= 30
DURATION ?= 600
SOAK_PNG ?= $(WS)/soak_map.png
COVER_DURATION ?= 1800
COVER_SCENE ?= cover_lounge
COVER_MIN_PROGRESS ?= 0.6
ROSENV := export PATH=/usr/bin:/bin:$$PATH PYTHONNOUSERSITE=1; unset PYTHONPATH PYTHONHOME; source $(WS)/devel/setup.bash
CATKIN := PATH=/usr/bin:/bin:$$PATH PYTHONNOUSERSITE=1 catkin_make -C $(WS) -j$(JOBS) \
          -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=ON

.PHONY: all deps build sim test test-unit test-asan bench soak soak-cover fuzz clean
all: build

deps:
	@$(ROOT)/scripts/install_deps.sh

build: deps
	@$(CATKIN) > $(WS)/build.log 2>&1 || { tail -n 60 $(WS)/build.log; echo "build failed (full log: $(WS)/build.log)"; exit 1; }
	@grep -E 'warning:' $(WS)/build.log | grep -v '^/usr/' || true
	@echo "build ok (log: $(WS)/build.log)"

sim: build
	@$(ROSENV); roslaunch $(ROOT)/launch/sim.launch $(ARGS)

test: build
	@$(ROOT)/scripts/run_tests.sh $(WS) $(JOBS)

test-unit: build
	@$(ROOT)/scripts/run_unit_tests.sh $(WS) $(JOBS)

test-asan: deps
	@$(ROOT)/scripts/run_asan_tests.sh $(WS) $(JOBS)

soak: build
	@$(ROSENV); catkin_make -C $(WS) explore_rostest > $(WS)/soak_build.log 2>&1 || { tail -n 30 $(WS)/soak_build.log; exit 1; }; \
	  rm -f $(SOAK_PNG); \
	  rostest --text --pkgdir=$(WS)/src/sl_bringup --package=sl_bringup $(WS)/src/sl_bringup/test/explore.test \
	  scene:=room seed:=$(or $(SEED),7) duration:=$(DURATION) min_travel:=$$(( $(DURATION) / 120 )) \
	  time_limit:=$$(( $(DURATION) + 180 )) memory_node:=/sl_manager map_png:=$(SOAK_PNG) check_stops:=false > $(WS)/soak.log 2>&1; \
	  grep -E 'explore |explore memory|explore progress|min clearance|FAIL|Failure|PASSED|passed|failed|SUMMARY|RESULT' $(WS)/soak.log; \
	  if [ -f $(SOAK_PNG) ]; then echo "map of the run: $(SOAK_PNG)"; fi; echo "log: $(WS)/soak.log"; \
	  ! grep -q '\[  FAILED  \]' $(WS)/soak.log && grep -q '\[  PASSED  \] 1 test' $(WS)/soak.log

soak-cover: build
	@$(ROSENV); catkin_make -C $(WS) cover_rostest > $(WS)/soak_build.log 2>&1 || { tail -n 30 $(WS)/soak_build.log; exit 1; }; \
	  home=$${ROS_HOME:-/tmp}; seed=$(or $(SEED),3); mins=$$(seq -s, 10 10 $$(( ($(COVER_DURATION) + 599) / 600 * 10 ))); \
	  rostest --text --pkgdir=$(WS)/src/sl_bringup --package=sl_bringup $(WS)/src/sl_bringup/test/cover.test \
	  scene:=$(COVER_SCENE) seed:=$$seed duration:=$(COVER_DURATION) min_progress:=$(COVER_MIN_PROGRESS) \
	  memory_node:=/sl_manager > $(WS)/soak_cover.log 2>&1; \
	  grep -E 'cover minute|cover: |cover memory|min clearance|FAILED|PASSED' $(WS)/soak_cover.log; \
	  /usr/bin/python3 $(ROOT)/scripts/cover_truth.py $(ROOT)/test/scenes/$(COVER_SCENE).yaml \
	    $$home/cover_$(COVER_SCENE)_$${seed}_path.txt --minutes=$$mins; \
	  echo "map: $$home/cover_$(COVER_SCENE)_$$seed.png; log: $(WS)/soak_cover.log"; \
	  ! grep -q '\[  FAILED  \]' $(WS)/soak_cover.log && grep -q '\[  PASSED  \] 1 test' $(WS)/soak_cover.log

bench: build
	@$(ROSENV); $(ROOT)/scripts/run_benchmarks.sh $(WS)

# Not part of `make test`: clang builds of the core sources with the sanitizers, in catkin_ws/build_fuzz.
fuzz: deps
	@FUZZ_SECONDS=$(FUZZ_SECONDS) FUZZ_JOBS=$(JOBS) $(ROOT)/scripts/run_fuzz.sh

clean:
	rm -rf $(WS)/build $(WS)/devel $(WS)/install $(WS)/build.log $(WS)/build_asan $(WS)/devel_asan
