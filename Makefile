# juggle — front door. `make train` and `make test` install what is missing, build, and run.
BUILD_DIR ?= build/release
PRESET    ?= release
CONFIG    ?= configs/right_foot.textproto
MINUTES   ?= 30
JOBS      ?= $(shell nproc)

.PHONY: deps configure build train train-toss test bench clean

deps:
	@bash scripts/install_deps.sh

configure: deps
	@cmake --preset $(PRESET) >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

# Trains for MINUTES of wall time (0: until Ctrl-C); continue later with --resume.
train: build
	$(BUILD_DIR)/juggle train --config=$(CONFIG) --minutes=$(MINUTES)

# Toss juggling (docs/toss.md): trains the catch and throw policies, then runs the evaluation.
train-toss: build
	$(BUILD_DIR)/juggle train --config=configs/toss_catch.textproto --iterations=2500
	$(BUILD_DIR)/juggle train --config=configs/toss_throw.textproto --iterations=8020
	$(BUILD_DIR)/juggle toss --eval --checkpoint=runs

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

bench: build
	$(BUILD_DIR)/juggle bench sim --config=$(CONFIG)

clean:
	rm -rf build
