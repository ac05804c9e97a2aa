# cloth_sim: the two commands of the README, plus a few helpers.
#   make run    installs what is missing, builds, runs the default demo scene
#   make test   installs what is missing, builds, runs every test (gate: catkin_test_results)
#   make bench  benchmark + stability sweep, results and plots in bench/results (docs/benchmark.md)
SHELL := /bin/bash
SCENE ?= hanging

.PHONY: run test build deps deps-bench clean bench stability

run: deps
	@bash scripts/build.sh
	@SCENE=$(SCENE) bash scripts/run_demo.sh

test: deps
	@bash scripts/test.sh

build: deps
	@bash scripts/build.sh

bench: deps-bench
	@bash bench/run.sh all

stability: deps
	@bash bench/run.sh stability

deps:
	@bash scripts/install_deps.sh

deps-bench:
	@bash scripts/install_deps.sh bench

clean:
	rm -rf .catkin_ws
