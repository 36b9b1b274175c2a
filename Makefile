# Glint top-level entry points. `make test` is what CI runs.
BUILD_DIR ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_GENERATOR ?= Ninja

# Debian bookworm packages Glint needs (see docs/architecture.md and third_party_notes/).
DEB_PACKAGES := build-essential cmake ninja-build pkg-config \
  libembree-dev libopenimageio-dev libopencv-core-dev openimageio-tools libopenexr-dev libpng-dev libjpeg-dev \
  libtinyobjloader-dev libtinygltf-dev libtbb-dev libgtest-dev libgmock-dev libbenchmark-dev \
  nlohmann-json3-dev libcli11-dev libeigen3-dev libdnnl-dev ocl-icd-opencl-dev \
  qt6-base-dev libgl-dev xvfb xauth fonts-dejavu-core \
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib
# qt6-base-dev (with libgl-dev, which Qt6Gui's CMake config asks for) builds the studio (gui/);
# xvfb, xauth and fonts-dejavu-core run its screenshot test in a real X server.
# libdnnl-dev (oneDNN) runs the learned filter unet; its CMake config needs the OpenCL
# headers and loader (ocl-icd-opencl-dev) although Glint uses only its CPU engine.
# pybind11-dev and python3-dev build the Python module (python/); numpy, pytest and matplotlib run
# its tests and the worked example of docs/python.md.

.PHONY: all deps build test clean demo bench bench-deps fuzz studio test-sanitize report test-slurm

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

# The studio on scenes/cornell (docs/studio.md); it renders at once.
studio: build
	$(BUILD_DIR)/bin/glint-studio scenes/cornell/scene.json

# Benchmark-only peers (Blender/Cycles, OpenCV, scikit-image; OpenImageIO's Python module for the
# glTF comparison with Cycles): not needed to build or test.
BENCH_PACKAGES := blender libopencv-dev libopencv-contrib-dev python3-skimage hyperfine python3-openimageio \
  python3-numpy

bench-deps:
	@./.ci/install-deps $(BENCH_PACKAGES)

bench: build bench-deps
	./lab/bench/run_all.sh $(BUILD_DIR)

# The speed-versus-accuracy report (docs/lab/tradeoffs.md): CSVs and PNG plots into docs/tradeoffs/,
# about 4 minutes on 2 cores; Cycles (blender) for the peer curve, matplotlib for the plots.
report: build
	@./.ci/install-deps blender python3-matplotlib
	./lab/bench/report/run.sh $(BUILD_DIR)

# A real one-node Slurm cluster on 127.0.0.1 (docs/distributed.md): slurmctld, slurmd and munged
# started from a temporary folder and stopped again; a 4-shard render of scenes/cornell (one shard
# failing once and requeued alone) and a 2-part bank through scripts/slurm/glint-farm, checked
# against single-machine runs. About 25 s on 2 cores after the build; needs root (the daemons run
# as root). Not part of `make test`; .ci/run runs it after `make test`.
test-slurm: build
	@./.ci/install-deps slurm-wlm munge
	./tests/slurm/cluster_test.sh $(BUILD_DIR)

# The unit tests under AddressSanitizer + UndefinedBehaviorSanitizer in build-sanitize/
# (docs/numerics.md, "Sanitizers"); sanitizer options and the reason for each live in
# tests/sanitize.env, the one leak suppression (libdbus, not Glint) and its reason in
# tests/lsan.supp.
SANITIZE_DIR ?= build-sanitize
test-sanitize: deps
	@test -f $(SANITIZE_DIR)/CMakeCache.txt || cmake -S . -B $(SANITIZE_DIR) -G "$(CMAKE_GENERATOR)" \
	  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGLINT_SANITIZE=ON -DGLINT_BUILD_BENCHMARKS=OFF
	cmake --build $(SANITIZE_DIR) -j $(JOBS)
	set -a && . tests/sanitize.env && LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp && \
	  cd $(SANITIZE_DIR) && ctest --output-on-failure -j $(JOBS)

# Fuzzing (docs/reliability.md): clang + libFuzzer + ASan/UBSan in build-fuzz/, each target for
# FUZZ_SECONDS (default 600, as each was run before its issue was resolved).
FUZZ_SECONDS ?= 600
fuzz: deps
	@./.ci/install-deps clang libclang-rt-14-dev
	@test -f build-fuzz/CMakeCache.txt || CC=clang CXX=clang++ cmake -S . -B build-fuzz -G "$(CMAKE_GENERATOR)" \
	  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGLINT_FUZZ=ON -DGLINT_BUILD_TESTS=OFF -DGLINT_BUILD_BENCHMARKS=OFF -DGLINT_BUILD_STUDIO=ON
	cmake --build build-fuzz -j $(JOBS) --target fuzz_scene_json fuzz_obj fuzz_texture fuzz_exr fuzz_gltf fuzz_tev \
	  fuzz_denoise_input fuzz_paint_script fuzz_session fuzz_bank_index fuzz_shard_merge fuzz_journal
	./tests/fuzz/run.sh build-fuzz $(FUZZ_SECONDS)

clean:
	rm -rf $(BUILD_DIR) build-fuzz $(SANITIZE_DIR) out
