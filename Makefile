# Glint top-level entry points. `make test` is what CI runs.
BUILD_DIR ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_GENERATOR ?= Ninja

# Debian bookworm packages Glint needs (see shared/DESIGN.md and third_party_notes/).
DEB_PACKAGES := build-essential cmake ninja-build pkg-config \
  libembree-dev libopenimageio-dev libopencv-core-dev openimageio-tools libopenexr-dev \
  libtinyobjloader-dev libtbb-dev libgtest-dev libgmock-dev libbenchmark-dev \
  nlohmann-json3-dev libcli11-dev
# Qt6 (qt6-base-dev), Eigen and xvfb join this list with the studio (gui/), which needs them.

.PHONY: all deps build test clean demo bench bench-deps

all: build

deps:
	@./.ci/install-deps $(DEB_PACKAGES)

build: deps
	@test -f $(BUILD_DIR)/CMakeCache.txt || cmake -S . -B $(BUILD_DIR) -G "$(CMAKE_GENERATOR)" -DCMAKE_BUILD_TYPE=RelWithDebInfo
	cmake --build $(BUILD_DIR) -j $(JOBS)

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

demo: build
	./scripts/demo.sh $(BUILD_DIR)

# Benchmark-only peers (Blender/Cycles, OpenCV, scikit-image): not needed to build or test.
BENCH_PACKAGES := blender libopencv-dev libopencv-contrib-dev python3-skimage hyperfine

bench-deps:
	@./.ci/install-deps $(BENCH_PACKAGES)

bench: build bench-deps
	./tests/perf/run_all.sh $(BUILD_DIR)

clean:
	rm -rf $(BUILD_DIR) out
