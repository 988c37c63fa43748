# Entry points. Each target first installs missing Debian packages (scripts/setup.sh).
BUILD        ?= build
BUILD_SAN    ?= build-sanitize
JOBS         ?= $(shell nproc)
CMAKE_FLAGS  ?=
SHARED_ASSETS ?= $(abspath ../shared/assets)

.PHONY: all setup build run test test-sanitize bench clean

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

$(BUILD_SAN)/build.ninja:
	# the editor is left out: Mesa and X11 keep allocations to exit, which LeakSanitizer reports
	cmake -S . -B $(BUILD_SAN) -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCAGEWRAP_SANITIZE=ON -DCAGEWRAP_GUI=OFF -DCAGEWRAP_SHARED_ASSETS=$(SHARED_ASSETS) $(CMAKE_FLAGS)

test-sanitize: setup $(BUILD_SAN)/build.ninja
	cmake --build $(BUILD_SAN) -j $(JOBS)
	cd $(BUILD_SAN) && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j $(JOBS)

bench: build
	bash scripts/bench.sh ./$(BUILD)/cagewrap $(SHARED_ASSETS)

clean:
	rm -rf $(BUILD) $(BUILD_SAN)
