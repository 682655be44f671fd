# leanfade front door. `make demo` and `make test` do all the set-up on a fresh Debian 12 machine.
BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc)
LEANFADE := $(BUILD_DIR)/tools/leanfade/leanfade
CMAKE_FLAGS ?=

# Extra ctest arguments, e.g. CTEST_ARGS="-LE gl" to leave out the OpenGL suites.
CTEST_ARGS ?=
# `make fuzz`: seconds per target, the build folder and the compilers (libFuzzer needs clang).
FUZZ_SECONDS ?= 60
FUZZ_BUILD_DIR ?= build-fuzz
FUZZ_CC ?= clang-14
FUZZ_CXX ?= clang++-14
FUZZ_TARGETS ?= fuzz_image_bake fuzz_ktx2 fuzz_obj fuzz_gltf fuzz_cli fuzz_preset fuzz_gnuplot
# Sanitizer settings of `make sanitize` (docs/robustness.md): leaks are errors, UBSan reports stop
# the test with a stack trace. No suppressions.
ASAN_CHECKS := detect_leaks=1:detect_stack_use_after_return=1
ASAN_CHECKS := $(ASAN_CHECKS):check_initialization_order=1:strict_init_order=1
SANITIZE_ENV := ASAN_OPTIONS=$(ASAN_CHECKS) UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# `make test-portable`: the build folder of the portable platform layer (README, "Platforms").
PORTABLE_BUILD_DIR ?= build-portable

# The interpreter of the Python module's benchmark (Debian's, with NumPy and Dask).
PYTHON ?= /usr/bin/python3

.PHONY: all deps configure build demo test test-portable bench sanitize fuzz fuzz-build fuzz-seeds web cli-doc \
	shader-tables clean format

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
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS) $(CTEST_ARGS)
	@# The Vulkan consumer's figures (validation messages, RMSE against leanfade render).
	@if [ -f $(BUILD_DIR)/test-tmp/vulkan_figures.txt ]; then cat $(BUILD_DIR)/test-tmp/vulkan_figures.txt; fi
	@# The WebGL2 page's figures (headless Chromium against leanfade render).
	@if [ -f $(BUILD_DIR)/test-tmp/webgl_figures.txt ]; then cat $(BUILD_DIR)/test-tmp/webgl_figures.txt; fi
	@# The WebGPU page's and the three.js package's figures (headless Chromium).
	@for f in webgpu_figures three_gpu_figures three_energy_figures; do \
		if [ -f $(BUILD_DIR)/test-tmp/$$f.txt ]; then cat $(BUILD_DIR)/test-tmp/$$f.txt; fi; done

# The WebGL2 example (examples/web, docs/integration.md): its data baked and exported, then
# served on http://127.0.0.1:$(WEB_PORT)/ until interrupted.
WEB_PORT ?= 8080
# docs/cli.md from the program's --help (the test docs.CliReferenceIsCurrent compares them).
cli-doc: build
	cmake -DLEANFADE=$(LEANFADE) -DOUTPUT=docs/cli.md -P cmake/GenerateCliDoc.cmake

# shaders/map_kinds.glsl and map_samplers.glsl written again from the map-kind table
# (leanfade/scene/detail/map_kinds.hpp); the test MapKinds.ShaderFilesAreTheTable checks them.
shader-tables: build
	LEANFADE_UPDATE_SHADER_TABLES=1 $(BUILD_DIR)/tests/scene/leanfade_scene_tests \
		--gtest_filter=MapKinds.ShaderFilesAreTheTable

web: build
	@mkdir -p examples/web/data
	$(LEANFADE) bake --builtin bumps --size 512 --bits 16f -o examples/web/data/bumps.ktx2 \
		--plateau-out examples/web/data/bumps.plateau.ktx2
	$(LEANFADE) shaders --lang glsl-es -o examples/web/data/shaders
	$(LEANFADE) shaders --lang wgsl -o examples/web/data/wgsl
	node examples/web/serve.mjs --data examples/web/data --port $(WEB_PORT)

# The portable platform layer (leanfade/core/detail/platform.hpp) forced on Linux, in its own build
# folder: only the libraries and test programs of core, io and scene are built, and their tests
# run (labels core, io, scene: no OpenGL), with platform.PortableCallsNoLinuxFunction.
test-portable: deps
	cmake -S . -B $(PORTABLE_BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) \
		-DLEANFADE_PORTABLE=ON -DLEANFADE_BUILD_VIEWER=OFF -DLEANFADE_BUILD_BENCH=OFF $(CMAKE_FLAGS)
	cmake --build $(PORTABLE_BUILD_DIR) -j $(JOBS) --target leanfade_gl_free_tests
	cd $(PORTABLE_BUILD_DIR) && ctest --output-on-failure -j $(JOBS) -L '^(core|io|scene)$$'

bench: build
	@LEANFADE_EXTRA_PACKAGES="libnvtt-bin libfilament-tools" scripts/install-deps.sh
	@mkdir -p out/bench
	$(BUILD_DIR)/bench/leanfade_bench_bake --benchmark_out=out/bench/bake.json --benchmark_out_format=json
	@echo "bake benchmark written to out/bench/bake.json"
	@maps="$$($(PYTHON) scripts/bake_off.py --list-corpus)"; \
	if [ -z "$$maps" ]; then \
		echo "compression error: no corpus map installed (docs/results.md §9 names the packages)"; \
	else \
		$(BUILD_DIR)/bench/leanfade_compression_error --out out/bench/compression $$maps && \
		echo "compression error on the corpus maps written to out/bench/compression"; \
	fi
	$(LEANFADE) bench --size 800x600 --frames 10 --warmup 2 --json out/bench/frames.json
	@echo "frame benchmark written to out/bench/frames.json (docs/perf.md)"
	PYTHONPATH=$(BUILD_DIR)/python $(PYTHON) bench/batch_throughput.py --leanfade $(LEANFADE) \
		--out out/bench/batch

# The whole test suite built with AddressSanitizer + UndefinedBehaviorSanitizer (Debug).
sanitize:
	$(SANITIZE_ENV) $(MAKE) test BUILD_DIR=build-sanitize BUILD_TYPE=Debug \
		CMAKE_FLAGS="-DLEANFADE_SANITIZE=ON -DLEANFADE_BUILD_BENCH=OFF"

# libFuzzer targets (fuzz/), instrumented with ASan + UBSan, in their own build folder.
fuzz-build:
	@LEANFADE_EXTRA_PACKAGES="clang-14 libclang-rt-14-dev zlib1g-dev" scripts/install-deps.sh
	cmake -S . -B $(FUZZ_BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
		-DCMAKE_C_COMPILER=$(FUZZ_CC) -DCMAKE_CXX_COMPILER=$(FUZZ_CXX) -DLEANFADE_BUILD_FUZZERS=ON \
		-DLEANFADE_BUILD_TESTS=OFF -DLEANFADE_BUILD_BENCH=OFF -DLEANFADE_BUILD_VIEWER=OFF
	cmake --build $(FUZZ_BUILD_DIR) -j $(JOBS) --target leanfade_fuzzers

# Each target for FUZZ_SECONDS on its committed seeds (never modified); crashes in
# $(FUZZ_BUILD_DIR)/artifacts/, summary in $(FUZZ_BUILD_DIR)/fuzz-summary.txt.
fuzz: fuzz-build
	scripts/run-fuzzers.sh $(FUZZ_BUILD_DIR) $(FUZZ_SECONDS) $(FUZZ_TARGETS)

# Rewrites the committed seed corpora fuzz/corpus/<target>/ (deterministic).
fuzz-seeds: fuzz-build
	$(FUZZ_BUILD_DIR)/fuzz/leanfade_fuzz_seeds fuzz/corpus

clean:
	rm -rf $(BUILD_DIR) build-sanitize $(FUZZ_BUILD_DIR)

format:
	find libs tools tests bench viewer -name '*.cpp' -o -name '*.hpp' | xargs clang-format -i
