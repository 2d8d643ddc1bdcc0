# The set-up commands of README.md. Each installs what is missing first.
#   make run       the packages building and rendering need, the `veil` command and the Python
#                  module only, then the default scene to out/default.png
#   make test      the test packages too, everything (test suites included), then ctest
#   make install   `veil`, its shaders and the Python package into PREFIX (default ~/.local)
#   make build     everything, without running anything (CI's first half of `make test`)
PRESET ?= release
BUILD := build/$(PRESET)
JOBS ?= $(shell nproc)
PREFIX ?= $(HOME)/.local

.PHONY: all deps deps-test configure build veil run test install clean

all: build

deps:
	@bash scripts/install-deps.sh

deps-test:
	@bash scripts/install-deps.sh --test

configure: deps
	@cmake --preset $(PRESET) >/dev/null

build: configure
	@cmake --build --preset $(PRESET) -j $(JOBS)

# What rendering needs: the command (its shaders are read from shaders/ at run time) and the
# Python module when the configuration has it; none of the test executables.
veil: configure
	@cmake --build --preset $(PRESET) -j $(JOBS) --target veil \
	  $$(grep -q '^VEIL_BUILD_PYTHON:BOOL=ON' $(BUILD)/CMakeCache.txt && echo _veil)

run: veil
	@mkdir -p out
	@$(BUILD)/src/veil render datasets/scenes/default.json -o out/default.png --report out/default.json
	@echo "image:  $(CURDIR)/out/default.png"
	@echo "report: $(CURDIR)/out/default.json"

test: deps-test build
	@ctest --preset $(PRESET)

install: veil
	@cmake --install $(BUILD) --prefix $(PREFIX)
	@echo "installed $(PREFIX)/bin/veil; put it on PATH with: export PATH=\"$(PREFIX)/bin:\$$PATH\""

clean:
	rm -rf build out
