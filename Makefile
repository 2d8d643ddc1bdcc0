# The two set-up commands of README.md. Both install what is missing first.
PRESET ?= release
BUILD := build/$(PRESET)
JOBS ?= $(shell nproc)

.PHONY: all deps configure build run test clean

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake --preset $(PRESET) >/dev/null

build: configure
	@cmake --build --preset $(PRESET) -j $(JOBS)

run: build
	@mkdir -p out
	@$(BUILD)/src/veil render datasets/scenes/default.json -o out/default.png --report out/default.json
	@echo "image:  $(CURDIR)/out/default.png"
	@echo "report: $(CURDIR)/out/default.json"

test: build
	@ctest --preset $(PRESET)

clean:
	rm -rf build out
