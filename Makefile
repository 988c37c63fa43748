# Entry points. Each target first installs missing Debian packages (scripts/setup.sh).
BUILD        ?= build
BUILD_SAN    ?= build-sanitize
BUILD_FUZZ   ?= build-fuzz
FUZZ_SECONDS ?= 60
# make test ends with a run of each fuzzer this long (0 = none; skipped without clang)
# make test: a fixed number of inputs per fuzzer from a fixed seed (reproducible; JOBS fuzzers at a time,
# about 2 min for all seven here)
TEST_FUZZ_RUNS ?= 100000
# make test runs the sanitizer suite (make test-sanitize) after the main one; 0 skips it
TEST_SANITIZE ?= 1
# make test's fuzz runs are built in the sanitizer tree (clang instruments it for libFuzzer too: one tree
# less to build), or in build-fuzz when the sanitizer suite is skipped
TEST_FUZZ_TREE = $(if $(filter 0,$(TEST_SANITIZE)),$(BUILD_FUZZ),$(BUILD_SAN))
JOBS         ?= $(shell nproc)
CMAKE_FLAGS  ?=
SHARED_ASSETS ?= $(abspath ../shared/assets)

.PHONY: all setup build run test check soak test-sanitize test-sanitize-full fuzz bench bench-gpu bench-peers clean

all: build

setup:
	@bash scripts/setup.sh

$(BUILD)/build.ninja:
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release -DCAGEWRAP_SHARED_ASSETS=$(SHARED_ASSETS) $(CMAKE_FLAGS)

build: setup $(BUILD)/build.ninja
	cmake --build $(BUILD) -j $(JOBS)

run: build
	./$(BUILD)/cagewrap

# every test: the suite, the same suite under ASan + UBSan, a short run of each fuzzer
test: check
ifneq ($(TEST_SANITIZE),0)
	$(MAKE) --no-print-directory test-sanitize
endif
ifneq ($(TEST_FUZZ_RUNS),0)
	FUZZ_RUNS=$(TEST_FUZZ_RUNS) FUZZ_SEED=1 bash scripts/fuzz.sh $(TEST_FUZZ_TREE) 0 $(JOBS) || [ $$? -eq 77 ]
endif

# the suite alone (the quick check while developing)
check: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# the editor soak for longer than make test's short run (SOAK_CYCLES cycles, two runs; about 20 s a cycle
# here: 20 cycles are about 13 minutes)
SOAK_CYCLES ?= 20
soak: build
	CAGEWRAP_SOAK_CYCLES=$(SOAK_CYCLES) ./$(BUILD)/cagewrap_tests --gtest_filter='EditorSoak.*'

# The sanitizer tree is built with clang when it is installed (scripts/setup.sh installs it for the
# fuzzers): on two cores its ASan + UBSan build of the whole tree took about 6 minutes against g++'s 18,
# which keeps make test under 50 minutes. g++ builds the product (make build) and the tree without clang.
SAN_COMPILERS ?= $(if $(shell command -v clang++ 2>/dev/null),-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++)

$(BUILD_SAN)/build.ninja:
	# the editor too: its GUI tests run it under the sanitizers (leak suppressions for libraries outside the
	# project, if ever needed, in tests/sanitize/lsan.supp; none is today).
	# Debug (assertions on) at -O1: the sanitizers' usual level, several times faster than -O0; -g1 keeps
	# the line tables the reports' stack traces need and compiles about a quarter faster than -g
	cmake -S . -B $(BUILD_SAN) -G Ninja $(SAN_COMPILERS) -DCMAKE_BUILD_TYPE=Debug "-DCMAKE_CXX_FLAGS_DEBUG=-g1 -O1" -DCAGEWRAP_SANITIZE=ON -DCAGEWRAP_GUI=ON -DCAGEWRAP_SHARED_ASSETS=$(SHARED_ASSETS) $(CMAKE_FLAGS)

# Left out of the sanitizer run (they run in make check; make test-sanitize-full runs them too), to keep
# make test under 50 minutes on two cores: the tests that kill processes in a loop (they test atomic
# saves, not memory; 144 s under ASan) and the tests of rig quality figures on whole characters (the
# same code runs under the sanitizers in the smaller tests of tests/stencil_smooth_test.cpp,
# attachment_fit_test.cpp and auto_cage_test.cpp; about 250 s) and the command-line scripts that run whole
# characters through auto cage, bind, fit, pose, export and simulation (about 710 s under ASan; the bad-input,
# character-loading and robustness scripts stay), and the automatic cages of whole characters (the demo, the
# mannequin, the demo's variants with fingers and a tail: about 330 s under ASan; the same builder runs under
# the sanitizers on the sphere, the deterministic, joint-detail and cancel tests and the smaller variants), two
# of the demo's baked-skin exports and one fidelity check (about 115 s; their siblings in the same files run),
# and the in-process automatic cage and baked-skin export of the demo (127 + 77 s under ASan; their cancel and
# refusal cases run), the in-process fidelity check of every clip run twice (10 s in release) and the deformer
# stack's rigs of the demo's walk (13 + 5.5 s in release), the editor's stack edited and checked against the rig (26 s) and its command-line scripts (22 s, the demo 16 s, the parametric driver 10 s; the other stack and
# fidelity cases run), and the baked exports of a three-deformer stack with a driver (16 s; the stack's binding
# cache case runs), and the three.js runtime check of every export mode (tests/cli/export_runtime.sh: 495 s under
# ASan, every cagewrap run of it sanitized; the exports it makes run under the sanitizers in export_test,
# gltf_writer_test and workspace_export_test: quantized, reordered, pose-driven).
# The FBX/Collada/DirectX CLI script (tests/cli/assimp.sh: 73 s under ASan, automatic rigs and exports of four
# characters) also runs at full speed only; its loader runs under the sanitizers in assimp_loader_test and
# editor_assimp_gui_test is a full-speed GUI test like the others.
SANITIZE_SKIP ?= ^Robustness\.Killed|^DefaultRig\.SmoothedStencilKeepsTheDemoWithinTheThresholds$$|^FittedAttachment\.(IsCloserToTheFilesSkinningThanTheTransferredWeights|TheEdgeTermLowersTheWorstStretch)$$|^MannequinDefaultRig\.|^AutoCage\.Mannequin(CageDeformsTheSkinLikeItsSkinning|FailingPointsAreThoseTheBindingMisses)$$|^DemoVariants\.TailWaveCurlsEveryTailBoneAndEveryFinger$$|^Variants/DefaultRigOnHardCharacters\.|^AutoCage\.(JointDetailWorksOnSeparateShells|DemoCharacterCage|MannequinGetsAClosedShellPerSegment)$$|^DemoVariants\.(TailHasFiveFingersPerHandAndATwelveBoneTail|CombinedArmsDownAndTailIsOneClosedSkin)$$|^Export\.(BakedSkinFitsTheKeyposeSweep|ReportsProgressAndStopsWhenCancelled)$$|^CheckFidelity\.ABadAttachmentFailsAndTheFailureNamesTheJoint$$|^cli\.(auto_cage|export|export_runtime|check|pose|simulate|project_storage|new_project|deformer|stack_demo|driver|assimp)$$|^WorkspaceEditsTest\.AnAutomaticCageIsBuiltInTheBackgroundAsOneUndoStep$$|^WorkspaceExportTest\.BakedSkinLoadsAgainWithACorrectivePerFrame$$|^WorkspaceFidelityTest\.TheCheckUsesTheSceneBindingAndMatchesAFreshRig$$|^DemoStack\.(ACopyOfTheOwnCageChangesNothingInOrderAndDoublesTheMotionInASum|ASculptedLayerUnderAHeadMaskMovesTheHeadOnly)$$|^WorkspaceStackTest\.AnActiveLayerIsSculptedAndTheViewIsWhatTheRigShips$$|^StackExport\.

# The editor under the sanitizers in make test-sanitize: the scripted GUI tests that open every hostile file
# from the File menu, draw offscreen (EGL) and in a window (Xvfb), edit the cage with undo and redo, paint
# sets, answer the unsaved-changes prompt, read a project with unknown fields and a corrupt preferences file
# (about 90 s of the editor at full speed, 120 s of ASan-built editor on two cores). The other GUI tests run under the
# sanitizers in make test-sanitize-full (their whole set is about 400 s at full speed, two to three times
# that under ASan) and at full speed in make check.
SANITIZE_EDITOR ?= ^(EditorHostileFilesGui\.|EditorOffscreen\.|EditorGui\.(BadFileKeepsRunningAndSaysWhy|MoveCageVerticesUndoRedoSave)$$|EditorTools\.(PaintingSetsRemovesFacesFromThePointsUnderTheBrush|OpeningWithUnsavedChangesAsksFirst)$$|EditorProjectGui\.UnknownFieldsAreLoggedAndWrittenBack$$|EditorFilesGui\.CorruptPreferencesAreNamedAndReplaced$$)
# The editor's runs check leaks too: the editor runs LeakSanitizer's check itself when it has torn its
# window down (app/editor.cpp, __lsan_do_leak_check), not at the process's exit, where the tracer once
# crashed among Mesa's threads (1 of 41 g++-built runs); 40 of 40 clang-built runs with leak checking on,
# half offscreen, half under Xvfb, were clean (docs/robustness.md).
SANITIZE_ENV = ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 LSAN_OPTIONS=suppressions=$(abspath tests/sanitize/lsan.supp):print_suppressions=0

test-sanitize: setup $(BUILD_SAN)/build.ninja
	cmake --build $(BUILD_SAN) -j $(JOBS)
	cd $(BUILD_SAN) && $(SANITIZE_ENV) ctest --output-on-failure -j $(JOBS) -E '$(SANITIZE_SKIP)|^Editor'
	cd $(BUILD_SAN) && $(SANITIZE_ENV) ctest --output-on-failure -j $(JOBS) -R '$(SANITIZE_EDITOR)'

test-sanitize-full: setup $(BUILD_SAN)/build.ninja
	cmake --build $(BUILD_SAN) -j $(JOBS)
	cd $(BUILD_SAN) && $(SANITIZE_ENV) ctest --output-on-failure -j $(JOBS)

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
