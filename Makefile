# juggle — front door. `make train` and `make test` install what is missing, build, and run.
BUILD_DIR ?= build/release
PRESET    ?= release
CONFIG    ?= configs/right_foot.textproto
JOBS      ?= $(shell nproc)

.PHONY: deps configure build train test bench clean

deps:
	@bash scripts/install_deps.sh

configure: deps
	@cmake --preset $(PRESET) >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

train: build
	$(BUILD_DIR)/juggle train --config=$(CONFIG)

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

bench: build
	$(BUILD_DIR)/juggle bench sim --config=$(CONFIG)

clean:
	rm -rf build
