# fsiopt build. PETSc comes from pkg-config (Debian's petsc-dev).
export OMPI_ALLOW_RUN_AS_ROOT := 1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM := 1
export OMPI_MCA_rmaps_base_oversubscribe := 1

# libopenblas0-serial: MUMPS's dense kernels; with Debian's reference BLAS the 3D tube's
# fluid factorization took 28 s instead of 5 s (46k unknowns). Serial: one thread per MPI rank.
DEB_PACKAGES := petsc-dev liblapack-dev libscotch-dev libyaml-dev libmuparser-dev python3-venv libhdf5-openmpi-dev gmsh pkg-config make python3-numpy python3-matplotlib python3-h5py libopenblas0-serial valgrind libegl1 libegl-mesa0 libgl1-mesa-dri
PYTHON := /usr/bin/python3
# libCEED (the fast FE operators, src/ceed/): PyPI's wheel carries the C library, its headers
# and ceed.pc; it goes into a private venv, and bin/fsiopt finds it by an rpath
CEED_VERSION := 0.12.0
VTK_VERSION := 9.7.2
VENV := $(CURDIR)/.deps/venv
CEED_DIR = $(firstword $(wildcard $(VENV)/lib/python3*/site-packages/libceed))
CEED_PC = PKG_CONFIG_PATH=$(CEED_DIR)/lib/pkgconfig pkg-config --define-variable=prefix=$(CEED_DIR)

CC      := mpicc
CFLAGS  ?= -O2 -g
# petscviewerhdf5.h includes hdf5.h, which Debian keeps under the MPI flavour's directory
# FSIOPT_ROOT: where a scene finds its default meshes when run from another directory
CFLAGS  += -Wall -Wextra -std=c11 -D_POSIX_C_SOURCE=200809L -DFSIOPT_ROOT='"$(CURDIR)"' -Iinclude -Isrc/scenes $(shell pkg-config --cflags PETSc 2>/dev/null) $(shell pkg-config --cflags hdf5-openmpi 2>/dev/null) $(shell $(CEED_PC) --cflags ceed 2>/dev/null)
LDLIBS  += $(shell pkg-config --libs PETSc 2>/dev/null) $(shell pkg-config --libs hdf5-openmpi 2>/dev/null) $(shell $(CEED_PC) --libs ceed 2>/dev/null) -Wl,-rpath,$(CEED_DIR)/lib -lscotch -llapack -lblas -lyaml -lmuparser -lm

SRC  := $(wildcard src/*.c src/*/*.c)
OBJ  := $(SRC:%.c=build/%.o) build/known_options.o build/version.o
GEO  := $(wildcard meshes/*.geo)
MSH  := $(GEO:.geo=.msh) meshes/tube3d-fluid-tets.msh meshes/tube3d-wall-tets.msh

.PHONY: all deps run test test-quick check-memory format clean clean-meshes bend3d-meshes FORCE

all: bin/fsiopt $(MSH)

deps:
	@missing=""; for p in $(DEB_PACKAGES); do dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  echo "make deps: installing$$missing"; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing >/dev/null; \
	else echo "make deps: all packages present"; fi
	@test -n "$(CEED_DIR)" -a -f "$(CEED_DIR)/lib/libceed.so" || { \
	  echo "make deps: libCEED $(CEED_VERSION) from PyPI into $(VENV)"; \
	  $(PYTHON) -m venv $(VENV) && $(VENV)/bin/pip install -q --no-deps libceed==$(CEED_VERSION); }
	@ls -d $(VENV)/lib/python3*/site-packages/vtkmodules >/dev/null 2>&1 || { \
	  echo "make deps: VTK $(VTK_VERSION) from PyPI into $(VENV) (ParaView's XDMF reader, for the tests)"; \
	  $(VENV)/bin/pip install -q --no-deps vtk==$(VTK_VERSION); }

bin/fsiopt: $(OBJ)
	@test -n "$(CEED_DIR)" || { echo "libCEED is missing: run make deps" >&2; exit 1; }
	@mkdir -p bin
	$(CC) -o $@ $(OBJ) $(LDLIBS)

# -MMD: every object depends on the headers it includes, private ones too
build/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -MMD -MP -c -o $@ $<

-include $(OBJ:.o=.d)

# the options fsiopt reads, from the string literals of its sources: an option nothing
# reads is refused with the nearest of these (src/common/options.c)
build/known_options.c: $(SRC) Makefile
	@mkdir -p build
	@{ echo '/* made by make from the option names in src/ */'; echo '#include <stddef.h>'; \
	  echo 'const char *const fsiopt_known_options[] = {'; \
	  grep -ohE '"-[a-z][a-z0-9_]*"' $(SRC) | sort -u | sed 's/$$/,/'; echo 'NULL};'; \
	  echo 'const char *const fsiopt_value_options[] = {'; \
	  grep -ohE '(Options(PositiveReal|NonNegativeReal|RealInRange|IntInRange)\(PetscOptionsObject, *|PetscOptions(Real|Int|Enum|String|EList|IntArray|RealArray|ScalarArray|FList)\(|PetscOptionsGet(Real|Int|String|Enum|IntArray|RealArray|EList)\([^"]*)"-[a-z0-9_]+"' $(SRC) \
	    | grep -oE '"-[a-z0-9_]+"' | sort -u | sed 's/$$/,/'; \
	  echo 'NULL};'; } > $@

build/known_options.o: build/known_options.c
	$(CC) -c -o $@ $<

# summary.json's "version": git describe of the tree built (rewritten only when it changes)
build/version.c: FORCE
	@mkdir -p build
	@v=$$(git -C $(CURDIR) describe --always --dirty 2>/dev/null || echo "unknown (built outside git)"); \
	  echo "const char fsiopt_version[] = \"$$v\";" > $@.new; cmp -s $@.new $@ || mv $@.new $@; rm -f $@.new

build/version.o: build/version.c
	$(CC) -c -o $@ $<

FORCE:

# Every mesh from a .geo, one rule: NAME.msh from NAME.geo, and its variants NAME-tets.msh
# (-setnumber simplex 1: tetrahedra) and NAME-nK.msh (-setnumber n K: level K) when there is
# no .geo of that name. The .geo's first line gives the dimension: `// gmsh -2` or `// gmsh -3`.
GEOINC := $(wildcard meshes/*.geoinc)
mesh_variant = $(if $(wildcard meshes/$(1).geo),,$(shell echo '$(1)' | sed -nE 's/-(tets|n[0-9]+)$$//p'))
mesh_geo = meshes/$(or $(call mesh_variant,$(1)),$(1)).geo
mesh_options = $(if $(call mesh_variant,$(1)),$(shell echo '$(1)' | sed -nE 's/.*-tets$$/-setnumber simplex 1/p; s/.*-n([0-9]+)$$/-setnumber n \1/p'))
mesh_flags = $(if $(call mesh_options,$*),$(call mesh_options,$*) )

.SECONDEXPANSION:
meshes/%.msh: $$(call mesh_geo,$$*) $(GEOINC)
	@dim=$$(sed -nE '1s,^// gmsh -([23])( .*)?$$,\1,p' $<); \
	  test -n "$$dim" || { echo "$<: the first line must be // gmsh -2 or // gmsh -3" >&2; exit 1; }; \
	  echo "gmsh -$$dim -format msh22 -v 2 $(mesh_flags)-o $@ $<"; \
	  gmsh -$$dim -format msh22 -v 2 $(mesh_flags)-o $@ $< >/dev/null

# the bent tube's finer levels (not built by `all`)
bend3d-meshes: $(foreach n,2 3,meshes/bend3d-fluid-n$(n).msh meshes/bend3d-wall-n$(n).msh)

clean-meshes:
	rm -f meshes/*.msh

# the seed's haemodynamic channel, 1000 steps; then its probe plot
run: deps
	$(MAKE) all
	bin/fsiopt -options_file options/channel2d.yaml -output_dir out/channel2d
	$(PYTHON) scripts/channel2d_figures.py probes out/channel2d
	@echo "outputs: out/channel2d/{summary.json,probes.csv,history.csv}, out/figures/channel2d-probes.png"

test: deps
	$(MAKE) all
	$(PYTHON) tests/run_tests.py

# the fast tier (tests/run_tests.py --quick): a test of every area, under 90 s
test-quick: deps
	$(MAKE) all
	$(PYTHON) tests/run_tests.py --quick

# a subset of runs under valgrind memcheck and PETSc's malloc trace (about 40 minutes: docs/testing.md)
check-memory: deps
	$(MAKE) all
	$(PYTHON) scripts/check_memory.py

# the C style of .clang-format (PETSc's, 120 columns) over every source and header
format:
	@command -v clang-format >/dev/null || { echo "make format: needs clang-format (apt-get install clang-format)"; exit 1; }
	clang-format -i $(SRC) $(wildcard include/*.h src/*/*.h)

clean:
	rm -rf build bin out meshes/*.msh
