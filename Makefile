# juggle — front door. `make train` and `make test` install what is missing, build, and run.
BUILD_DIR ?= build/release
PRESET    ?= release
CONFIG    ?= configs/right_foot_recipe.textproto
MINUTES   ?= 30
BENCH_CONFIG ?= configs/right_foot.textproto
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

# Toss juggling (docs/toss.md, docs/results.md): the single-arm catch and throw policies, then
# two rounds of training inside the two-arm loop, a held-out choice of the round-2 catch
# checkpoint, and the evaluation protocol. About 2 h 40 min on 2 cores.
J := $(BUILD_DIR)/juggle
TOSS_PARTNERS := runs/toss_partners
train-toss: build
	$(J) train --config=configs/toss_catch.textproto --iterations=2500
	$(J) train --config=configs/toss_throw.textproto --iterations=8020
	mkdir -p $(TOSS_PARTNERS)
	$(J) export-policy --checkpoint=runs/toss_catch --out=$(TOSS_PARTNERS)/catch_r0.jglpolicy
	$(J) export-policy --checkpoint=runs/toss_throw --out=$(TOSS_PARTNERS)/throw_r0.jglpolicy
	$(J) train --config=configs/toss_loop1_throw.textproto --init_from=runs/toss_throw --minutes=25
	$(J) train --config=configs/toss_loop1_catch.textproto --init_from=runs/toss_catch --minutes=25
	$(J) export-policy --checkpoint=runs/toss_loop1_throw --out=$(TOSS_PARTNERS)/throw_r1.jglpolicy
	$(J) train --config=configs/toss_loop2_catch.textproto --init_from=runs/toss_loop1_catch --minutes=25
	scripts/rank_toss_checkpoints.sh catch runs/toss_loop2_catch/checkpoints runs/toss_loop1_throw \
	  3,4,5,531,53,441,6,7 | tee runs/toss_loop2_catch/ranking.txt
	$(J) toss --eval --throw=runs/toss_loop1_throw \
	  --catch=$$(tail -n 1 runs/toss_loop2_catch/ranking.txt | cut -d' ' -f3)

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

bench: build
	$(BUILD_DIR)/juggle bench sim --config=$(BENCH_CONFIG)

clean:
	rm -rf build
