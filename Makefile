# Entry points. Each target first installs missing Debian packages (scripts/setup.sh).
BUILD        ?= build
BUILD_SAN    ?= build-sanitize
BUILD_FUZZ   ?= build-fuzz
FUZZ_SECONDS ?= 60
# make test can run each fuzzer this long after ctest (skipped without clang). 0 by default: the
# harnesses' clang build takes over 10 minutes on 2 cores and has not been run in CI yet.
TEST_FUZZ_SECONDS ?= 0
JOBS         ?= $(shell nproc)
CMAKE_FLAGS  ?=
SHARED_ASSETS ?= $(abspath ../shared/assets)

.PHONY: all setup build run test test-sanitize fuzz bench bench-gpu bench-peers clean

all: build

setup:
	@bash scripts/setup.sh

$(BUILD)/build.ninja:
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release -DCAGEWRAP_SHARED_ASSETS=$(SHARED_ASSETS) $(CMAKE_FLAGS)

build: setup $(BUILD)/build.ninja
	cmake --build $(BUILD) -j $(JOBS)

run: build
	./$(BUILD)/cagewrap

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)
ifneq ($(TEST_FUZZ_SECONDS),0)
	bash scripts/fuzz.sh $(BUILD_FUZZ) $(TEST_FUZZ_SECONDS) $(JOBS) || [ $$? -eq 77 ]
endif

$(BUILD_SAN)/build.ninja:
	# the editor is left out: Mesa and X11 keep allocations to exit, which LeakSanitizer reports
	cmake -S . -B $(BUILD_SAN) -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCAGEWRAP_SANITIZE=ON -DCAGEWRAP_GUI=OFF -DCAGEWRAP_SHARED_ASSETS=$(SHARED_ASSETS) $(CMAKE_FLAGS)

test-sanitize: setup $(BUILD_SAN)/build.ninja
	cmake --build $(BUILD_SAN) -j $(JOBS)
	cd $(BUILD_SAN) && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j $(JOBS)

# libFuzzer harnesses (tests/fuzz/) under ASan and UBSan, FUZZ_SECONDS each (clang; see docs/robustness.md)
fuzz: setup
	bash scripts/fuzz.sh $(BUILD_FUZZ) $(FUZZ_SECONDS) $(JOBS)

bench: build
	bash scripts/bench.sh ./$(BUILD)/cagewrap $(SHARED_ASSETS)

# the GPU path (OpenGL 4.3 compute): bench --gpu headless, 4M-vertex memory, the editor's frame split
bench-gpu: build
	bash scripts/bench.sh ./$(BUILD)/cagewrap $(SHARED_ASSETS) gpu

# cagewrap against Blender's Surface Deform on the same meshes (bench/peers/; skipped without blender)
bench-peers: build
	bash bench/peers/run.sh ./$(BUILD)/cagewrap $(SHARED_ASSETS)

clean:
	rm -rf $(BUILD) $(BUILD_SAN) $(BUILD_FUZZ)
