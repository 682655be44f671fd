# leanfade front door. `make demo` and `make test` do all the set-up on a fresh Debian 12 machine.
BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc)
LEANFADE := $(BUILD_DIR)/tools/leanfade/leanfade
CMAKE_FLAGS ?=

.PHONY: all deps configure build demo test bench sanitize fuzz clean format

all: build

deps:
	@scripts/install-deps.sh

$(BUILD_DIR)/build.ninja:
	cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) $(CMAKE_FLAGS)

configure: deps $(BUILD_DIR)/build.ninja

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

demo: build
	@mkdir -p out
	$(LEANFADE) render --scene teapot --bumps bumps --techniques bump,lean,fade --distances 3,24 --zoom -o out/teaser.png
	@echo "teaser written to $(CURDIR)/out/teaser.png"

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

bench: build
	@LEANFADE_EXTRA_PACKAGES=libnvtt-bin scripts/install-deps.sh
	@mkdir -p out/bench
	$(BUILD_DIR)/bench/leanfade_bench_bake --benchmark_out=out/bench/bake.json --benchmark_out_format=json
	@echo "bake benchmark written to out/bench/bake.json"

sanitize:
	$(MAKE) test BUILD_DIR=build-sanitize BUILD_TYPE=Debug CMAKE_FLAGS="-DLEANFADE_SANITIZE=ON -DLEANFADE_BUILD_BENCH=OFF"

clean:
	rm -rf $(BUILD_DIR) build-sanitize

format:
	find libs tools tests bench viewer -name '*.cpp' -o -name '*.hpp' | xargs clang-format -i
