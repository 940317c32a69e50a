# juggle — front door. `make train` and `make test` install what is missing, build, and run.
BUILD_DIR ?= build/release
PRESET    ?= release
CONFIG    ?= configs/right_foot_recipe.textproto
MINUTES   ?= 30
BENCH_CONFIG ?= configs/right_foot.textproto
JOBS      ?= $(shell nproc)

.PHONY: deps configure build train train-toss test test-fuzz test-deploy test-netfaults test-sanitize fuzz bench clean

deps:
	@bash scripts/dev/install_deps.sh

configure: deps
	@cmake --preset $(PRESET) >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

# Trains for MINUTES of wall time (0: until Ctrl-C); continue later with --resume.
train: build
	$(BUILD_DIR)/juggle train --config=$(CONFIG) --minutes=$(MINUTES)

# Toss juggling (docs/toss.md, docs/results.md): residual catch and throw policies on the base
# controllers, trained side by side in the two-arm loop on every pattern and on transitions, a
# held-out ranking of their checkpoints, the exported pair (runs/toss_pair/) and the evaluation
# protocol. About 30 min on 2 cores. The pair it produced is shipped in policies/toss/.
train-toss: build
	JUGGLE=$(BUILD_DIR)/juggle scripts/experiments/train_toss.sh runs

# Every test of ctest but the deployment tests (label `deploy`, `make test-deploy`) and the
# network-fault tests (label `netfaults`, `make test-netfaults`); this
# includes replaying each fuzzer's corpus and past crashes (FuzzCorpus.*) through this build.
# Twice as many tests at a time as cores: many tests wait (on child processes, sockets, the
# soak's clock) more than they compute; the long ones start first (COST, CMakeLists.txt).
TEST_JOBS ?= $(shell echo $$(( 2 * $(JOBS) )))
test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(TEST_JOBS) -LE 'deploy|netfaults'

# Each libFuzzer harness briefly (FUZZ_BRIEF seconds each) on its own clang build of the
# libraries (build/fuzz). Run by .ci/run after `make test`.
FUZZ_BRIEF ?= 10
test-fuzz: deps
	scripts/dev/fuzz.sh $(FUZZ_BRIEF)

# The deployment tests on real engines (docs/cluster.md): images built with podman, the k8s
# manifests under `podman kube play`, the Slurm job on a single-node Slurm. Needs root.
test-deploy: build
	@bash scripts/dev/install_deps.sh --deploy
	cd $(BUILD_DIR) && ctest --output-on-failure -L deploy

# The rollout service under network faults (docs/reliability.md, "Network faults"): a learner
# and 4 workers in network namespaces (root; skipped with a message where namespaces are not
# allowed) through the fault proxy, token and TLS on, latency, loss, partitions, a stall and a
# learner restart on a seeded schedule (NETFAULTS_SEED), one test at a time. About 5 minutes.
NETFAULTS_SEED ?= 47
test-netfaults: build
	@bash scripts/dev/install_deps.sh --netfaults
	cd $(BUILD_DIR) && JUGGLE_NETFAULTS_SEED=$(NETFAULTS_SEED) ctest --output-on-failure -L netfaults

# The service's tests under ASan+UBSan and TSan (docs/reliability.md).
test-sanitize: deps
	scripts/dev/test_sanitize.sh

# Fuzzing: every harness for FUZZ_SECONDS (docs/reliability.md).
FUZZ_SECONDS ?= 300
fuzz: deps
	scripts/dev/fuzz.sh $(FUZZ_SECONDS)

bench: build
	$(BUILD_DIR)/juggle bench sim --config=$(BENCH_CONFIG)

clean:
	rm -rf build
