# Thin wrapper over CMake presets. `make run` and `make test` work on a fresh Debian 12 machine.
JOBS ?= $(shell nproc)
BUILD := build/release
DEMO_OUT ?= results/elastic_bar

.PHONY: setup build run test test-fast bench clean

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

bench: build
	@$(BUILD)/bin/spall_bench --benchmark_out=$(BUILD)/bench.json --benchmark_out_format=json
	@echo "JSON: $(BUILD)/bench.json"

clean:
	rm -rf build
