# Thin wrapper over CMake presets. `make run` and `make test` work on a fresh Debian 12 machine.
JOBS ?= $(shell nproc)
BUILD := build/release
DEMO_OUT ?= results/elastic_bar

DRILLING_OUT ?= results/friction_drilling

.PHONY: setup build run test test-fast test-sanitize fuzz bench drilling drilling-study clean

setup:
	@bash tools/setup.sh

build: setup
	@cmake --preset release >/dev/null
	@cmake --build --preset release -j $(JOBS)

run: build
	$(BUILD)/bin/spall run examples/elastic_bar/bar.k -o $(DEMO_OUT)
	@echo "Results in $(DEMO_OUT): open $(DEMO_OUT)/d3plot.pvd in ParaView (File > Open), glstat.csv holds the energies."

test: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS) --timeout 900

test-fast: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS) -LE slow

# The whole test suite built with AddressSanitizer and UndefinedBehaviorSanitizer (-O2); slower, so
# a longer timeout per test. The test preset names tools/lsan.supp (libgomp's own allocations).
test-sanitize: setup
	@cmake --preset sanitize >/dev/null
	@cmake --build --preset sanitize -j $(JOBS)
	@ctest --preset sanitize -j $(JOBS) --timeout 3600

# The keyword reader's libFuzzer target (clang, ASan, UBSan) for FUZZ_SECONDS on one core. The
# corpus grows in FUZZ_WORK; a crash is written to FUZZ_WORK/artifacts and stops the run.
FUZZ_SECONDS ?= 600
FUZZ_WORK ?= build/fuzz/work
fuzz:
	@bash tools/setup.sh fuzz
	@cmake --preset fuzz >/dev/null
	@cmake --build --preset fuzz -j $(JOBS)
	bash fuzz/run.sh $(FUZZ_SECONDS) $(FUZZ_WORK)

bench: build
	@$(BUILD)/bin/spall_bench --benchmark_out=$(BUILD)/bench.json --benchmark_out_format=json
	@echo "JSON: $(BUILD)/bench.json"

# The friction-drilling demo (examples/friction_drilling): the run, then its force histories and particles.
drilling: build
	$(BUILD)/bin/spall run examples/friction_drilling/drilling.k -o $(DRILLING_OUT)
	/usr/bin/python3 tools/drilling_forces.py $(DRILLING_OUT) --label "m2, COF 0.2" --csv $(DRILLING_OUT)/forces.csv \
	  -o $(DRILLING_OUT)/forces.png
	/usr/bin/python3 tools/drilling_particles.py $(DRILLING_OUT)/d3plot_*.vtu | tail -n 1

# Seed 001's parameter studies, the scaling check and the FEM comparison (LEVEL=coarse or full).
drilling-study: build
	bash tools/drilling_study.sh results/drilling_study

clean:
	rm -rf build
