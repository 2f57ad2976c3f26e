# MBSPH build. `make` builds build/mbsph; `make test` runs every test;
# `make run` runs the default case and draws its pictures. See README.md.
# a recipe that fails leaves no target behind (a generated file cut short would look up to date)
.DELETE_ON_ERROR:
ifeq ($(origin FC),default)
FC        = mpif90
endif
HDF5_INC  ?= /usr/include/hdf5/openmpi
HDF5_LIB  ?= /usr/lib/x86_64-linux-gnu/hdf5/openmpi
# FFTW 3: its Fortran interface fftw3.f03 is included by src/wave_fftw.f90 only
FFTW_INC  ?= /usr/include
FFTW_LIB  ?= /usr/lib/x86_64-linux-gnu
# ARCH: -march=native here; `make PORTABLE=1` for a cluster build whose
# login and compute nodes differ.
ifdef PORTABLE
ARCH      ?= -mtune=generic
else
ARCH      ?= -march=native
endif
WARN      = -std=f2008 -Wall -Wextra -fimplicit-none
# -flto: the pair loops call the grid's small functions (grid_ranges) and the
# step the integrators' loops across modules; link-time optimisation inlines
# them (4 % on both bench cases, doc/performance.md)
# no inlining of a function called once: link-time optimisation otherwise inlines the pair
# list's builder into the step, 1.2x slower on the breakwater (doc/performance.md)
OPT_release = -O3 $(ARCH) -flto=auto -fno-inline-functions-called-once
OPT_debug   = -g -O0 -fcheck=all -ffpe-trap=invalid,zero,overflow -fbacktrace
PYTHON    = .venv/bin/python
# the specialised pair loops share one interface; each variant leaves the
# arguments of the models it does not use untouched, by design
XFLAGS_fluid_forces = -Wno-unused-dummy-argument
XFLAGS_wave_fftw = -I$(FFTW_INC)
LIBS      = -L$(HDF5_LIB) -lhdf5_fortran -lhdf5 -L$(FFTW_LIB) -lfftw3

# every object is built twice: build/ (release) and build/debug/
SRC       := $(sort $(wildcard src/*.f90 src/*.F90))
NAMES     := $(basename $(notdir $(SRC)))
LIBNAMES  := $(filter-out mbsph,$(NAMES))
UNIT_SRC  := $(sort $(wildcard tests/unit/test_*.f90))
UNIT      := $(basename $(notdir $(UNIT_SRC)))

.PHONY: mbsph3d run3d all debug deps test wave-heights unit unit-debug unit-3d run dambreak breakwater breakwater_core porous_waves lint bench bench-mpi bench-effects clean figures paper stability study porous damage
all: build/mbsph
debug: build/debug/mbsph

define variant # $(1)=build dir, $(2)=flags, $(3)=directory of the generated code (its dimension)
$(1)/obj/%.o: src/%.f90 | $(1)/obj $(1)/mod
	$$(FC) $(2) -I$$(HDF5_INC) -Isrc -J$(1)/mod $$(XFLAGS_$$*) -c $$< -o $$@
$(1)/obj/%.o: src/%.F90 | $(1)/obj $(1)/mod
	$$(FC) $(2) -I$$(HDF5_INC) -Isrc -I$(3) -J$(1)/mod $$(XFLAGS_$$*) -c $$< -o $$@
$(addprefix $(1)/obj/,fluid_forces.o kernel_correction.o bc_mdbc.o particles.o nbr_list.o contact.o): \
  $(addprefix $(3)/,$(addsuffix .inc,$(GEN_NAMES)))
$(1)/mbsph: $(addprefix $(1)/obj/,$(addsuffix .o,$(NAMES)))
	$$(FC) $(2) -o $$@ $$^ $$(LIBS)
$(1)/obj/testing.o: tests/unit/testing.f90 | $(1)/obj $(1)/mod
	$$(FC) $(2) -J$(1)/mod -c $$< -o $$@
$(1)/tests/%: tests/unit/%.f90 $(1)/obj/testing.o $(addprefix $(1)/obj/,$(addsuffix .o,$(LIBNAMES))) | $(1)/tests
	$$(FC) $(2) -I$(1)/mod -J$(1)/tests -o $$@ $$< $(1)/obj/testing.o \
	  $(addprefix $(1)/obj/,$(addsuffix .o,$(LIBNAMES))) $$(LIBS)
$(1)/jonswap_signal: tools/jonswap_signal.f90 $(addprefix $(1)/obj/,$(addsuffix .o,$(LIBNAMES))) | $(1)/tests
	$$(FC) $(2) -I$(1)/mod -J$(1)/tests -o $$@ $$< $(addprefix $(1)/obj/,$(addsuffix .o,$(LIBNAMES))) $$(LIBS)
$(1)/deps.mk: $(SRC) tools/fdeps.sh | $(1)/obj
	GENDIR=$(3) tools/fdeps.sh $(1)/obj $(SRC) > $$@
$(1)/obj $(1)/mod $(1)/tests:
	mkdir -p $$@
endef
# code generated from a list (fypp, installed by make deps): the pair-loop variants
FYPP := .venv/bin/fypp
# the space dimensions are set in one place, src/constants.f90 (ndim); the generated code takes them
# from there. The 3D build (build/mbsph3d) compiles the same sources with ndim = 3 in a copy of it.
NDIM := $(shell sed -n 's/^ *integer, parameter :: ndim = \([0-9]\) .*/\1/p' src/constants.f90)
GEN_NAMES := fluid_variants fluid_dispatch pre_pairs pre_decl mdbc_ghosts nbr_pairs shepard_pairs contact_pairs \
             particle_decl particle_table particle_slots
define gen_rules # $(1)=directory of the generated code, $(2)=its space dimensions
$(1)/fluid_variants.inc: src/fluid_variants.fypp src/components.fypp src/fluid_pairs.inc src/fluid_pair_body.inc \
                         src/stencil.fypp src/constants.f90 | $(1) $(FYPP)
	$(FYPP) -DNDIM=$(2) -DPART="'loops'" $$< $$@
$(1)/fluid_dispatch.inc: src/fluid_variants.fypp src/components.fypp src/constants.f90 | $(1) $(FYPP)
	$(FYPP) -DNDIM=$(2) -DPART="'dispatch'" $$< $$@
$(1)/pre_pairs.inc: src/pre_pairs.fypp src/components.fypp src/constants.f90 | $(1) $(FYPP)
	$(FYPP) -DNDIM=$(2) -DPART="'body'" $$< $$@
$(1)/pre_decl.inc: src/pre_pairs.fypp src/components.fypp src/constants.f90 | $(1) $(FYPP)
	$(FYPP) -DNDIM=$(2) -DPART="'decl'" $$< $$@
$(1)/mdbc_ghosts.inc: src/mdbc_ghosts.fypp src/components.fypp src/constants.f90 | $(1) $(FYPP)
	$(FYPP) -DNDIM=$(2) $$< $$@
# the passes over the one traversal of pairs, src/stencil.fypp
$(1)/nbr_pairs.inc $(1)/shepard_pairs.inc $(1)/contact_pairs.inc: $(1)/%.inc: src/%.fypp src/stencil.fypp \
                                                                  src/constants.f90 | $(1) $(FYPP)
	$(FYPP) -DNDIM=$(2) $$< $$@
$(1)/particle_%.inc: src/particle_fields.fypp src/constants.f90 | $(1) $(FYPP)
	$(FYPP) -DNDIM=$(2) -DPART="'$$*'" $$< $$@
$(1):
	mkdir -p $$@
endef
$(eval $(call gen_rules,build/gen,$(NDIM)))
$(eval $(call gen_rules,build/3d/gen,3))
$(FYPP):
	@bash tools/deps.sh

$(eval $(call variant,build,$(WARN) $(OPT_release),build/gen))
$(eval $(call variant,build/debug,$(WARN) $(OPT_debug),build/gen))
# the 3D solver: the same sources, constants with ndim = 3 (doc/3d.md)
$(eval $(call variant,build/3d,$(WARN) $(OPT_release),build/3d/gen))
$(eval $(call variant,build/3d/debug,$(WARN) $(OPT_debug),build/3d/gen))
build/3d/src/constants.f90: src/constants.f90
	mkdir -p build/3d/src
	sed 's/integer, parameter :: ndim = 2 /integer, parameter :: ndim = 3 /' $< > $@
	grep -q 'ndim = 3 ' $@
build/3d/obj/constants.o: build/3d/src/constants.f90 | build/3d/obj build/3d/mod
	$(FC) $(WARN) $(OPT_release) -Jbuild/3d/mod -c build/3d/src/constants.f90 -o $@
build/3d/debug/obj/constants.o: build/3d/src/constants.f90 | build/3d/debug/obj build/3d/debug/mod
	$(FC) $(WARN) $(OPT_debug) -Jbuild/3d/debug/mod -c build/3d/src/constants.f90 -o $@
# a copy renamed into place: a run of the old binary keeps it
build/mbsph3d: build/3d/mbsph
	cp $< $@.tmp && mv $@.tmp $@
mbsph3d: build/mbsph3d
-include build/deps.mk build/debug/deps.mk build/3d/deps.mk build/3d/debug/deps.mk

deps:
	@bash tools/deps.sh

# the tools written against the solver's modules are built with the unit tests, so that they keep compiling
unit: build/mbsph build/jonswap_signal $(addprefix build/tests/,$(UNIT))
	@fail=0; for t in $(UNIT); do build/tests/$$t || fail=1; done; exit $$fail
unit-debug: build/debug/mbsph $(addprefix build/debug/tests/,$(UNIT)) unit-3d
	@fail=0; for t in $(UNIT); do build/debug/tests/$$t || fail=1; done; exit $$fail

# the unit tests that hold in any dimension, and tests/unit3d (the 3D rigid body), run in the
# 3D build of the solver's modules (build/3d/debug, debug checks on)
UNIT_3D := test_kernel test_tensor test_grid test_repulsive
UNIT3D_SRC := $(sort $(wildcard tests/unit3d/test_*.f90))
build/3d/debug/tests/%: tests/unit3d/%.f90 build/3d/debug/obj/testing.o \
  $(addprefix build/3d/debug/obj/,$(addsuffix .o,$(LIBNAMES))) | build/3d/debug/tests
	$(FC) $(WARN) $(OPT_debug) -Ibuild/3d/debug/mod -Jbuild/3d/debug/tests -o $@ $< build/3d/debug/obj/testing.o \
	  $(addprefix build/3d/debug/obj/,$(addsuffix .o,$(LIBNAMES))) $(LIBS)
UNIT_3D_BIN := $(addprefix build/3d/debug/tests/,$(UNIT_3D) $(basename $(notdir $(UNIT3D_SRC))))
unit-3d: $(UNIT_3D_BIN)
	@fail=0; for t in $^; do $$t || fail=1; done; exit $$fail

# the whole suite: unit tests on the release and the debug build, then the
# integration tests (cases, restart, bad input, output, ParaView, wave heights) on
# TEST_JOBS pytest workers (pytest-xdist; default: the number of cores). The long
# wave-height runs come first (tests/conftest.py); --maxschedchunk=1 makes xdist deal
# them out one per worker instead of giving one worker a block of them all.
TEST_JOBS ?= $(shell nproc)
test: deps
	$(MAKE) -j2 build/mbsph build/debug/mbsph build/mbsph3d $(UNIT_3D_BIN)
	$(MAKE) unit unit-debug
	$(PYTHON) -m pytest -q -n $(TEST_JOBS) --maxschedchunk=1 tests

# all four wave-height flumes, with the line each prints (doc/waves.md); 1.7e9 particle-steps, most of the time of make test
wave-heights: deps build/mbsph
	$(PYTHON) -m pytest -q -rA -n $(TEST_JOBS) --maxschedchunk=1 tests/test_waves.py -k height_2_to_4

# mpirun as root (containers, CI) needs these flags; elsewhere they are harmless
MPIRUN    ?= mpirun $(if $(filter 0,$(shell id -u)),--allow-run-as-root) --oversubscribe
RANKS     ?= 2

# the default scene: regular waves on a small breakwater with cube armour (doc/breakwater.md)
run: deps build/mbsph
	$(MPIRUN) -np $(RANKS) build/mbsph input/demo_breakwater.nml
	$(PYTHON) -m post.plot_field OUT/demo_breakwater --field velocity --times 2.0 3.5 5.0 6.0
	$(PYTHON) -m post.armour OUT/demo_breakwater --out OUT/demo_breakwater

# a small 3D scene on two ranks (doc/3d.md): cubes on a slope and a floating one in a
# tank with walls all round, drawn in perspective at four times
run3d: deps build/mbsph3d
	$(MPIRUN) -np $(RANKS) build/mbsph3d input/run3d.nml
	$(PYTHON) -m post.plot_3d OUT/run3d --times 0.0 0.4 0.8 1.2

# the dam break of the foundation (Martin and Moyce), with its comparison
dambreak: deps build/mbsph
	build/mbsph input/dambreak.nml
	$(PYTHON) -m post.plot_field OUT/dambreak --field pressure
	$(PYTHON) -m post.dambreak OUT/dambreak

# the coarse breakwater with regular and irregular armour placement, each on an
# impermeable and on a porous core: a settling run in still water (1 s), continued under
# waves by a restart; armour figures and the table of the four against the laboratory
# ranges (doc/breakwater.md); cost measured there.
# BW_T0: start of the window in which the wave height is measured at gauge 3 (Ns);
# BW_DOC: where the figures (BW_DOC/img) and the table go. A short trial lowers BW_END
# and BW_T0 and writes elsewhere than doc/: BW_END=3 BW_T0=1.5 BW_DOC=OUT/breakwater_trial.
BW_END ?= 12.0
BW_T0  ?= 5
BW_DOC ?= doc
BW_CASES := regular irregular regular_porous irregular_porous
breakwater: deps build/mbsph
	@for pl in $(BW_CASES); do \
	  echo "== settling: $$pl"; \
	  $(MPIRUN) -np $(RANKS) build/mbsph input/breakwater/$$pl.nml > /dev/null || exit 1; \
	  sed -e "s/t_end = 1.0/t_end = $(BW_END)/" -e "s/overwrite = .true./restart = .true./" \
	    input/breakwater/$$pl.nml > OUT/breakwater_$$pl/waves.nml; \
	  echo "== waves: $$pl (restart of the settled layer until t = $(BW_END) s)"; \
	  $(MPIRUN) -np $(RANKS) build/mbsph OUT/breakwater_$$pl/waves.nml > /dev/null || exit 1; \
	  $(PYTHON) -m post.armour OUT/breakwater_$$pl --gauge 3 --t-start $(BW_T0) --out $(BW_DOC)/img/breakwater_$$pl || exit 1; \
	done
	$(PYTHON) -m post.armour $(foreach c,$(BW_CASES),OUT/breakwater_$(c)) --gauge 3 --t-start $(BW_T0) \
	  --table $(BW_DOC)/breakwater_table.md --out $(BW_DOC)/img

# damage under test series like a laboratory's (doc/damage.md): SERIES names a series file
# (study/series/*.toml): the settling run, then steps of irregular waves of rising Hs,
# each a restart of the last; per step the incident Hm0 and H2% at the toe, Ns and the
# units displaced, into <out>/series.csv and series.png. The default is the short trial
# (three steps of a few waves, under 10 minutes on 2 cores); a finished step is kept.
SERIES ?= study/series/trial.toml
damage: deps build/mbsph
	$(PYTHON) -m post.series $(SERIES)

lint: deps
	bash tools/lint.sh

# the seed paper's cases TC1a, TC1b, TC2, TC3 with every contact model, and their
# figures (doc/img/paper_*.png); TC4 (in water) with `make paper`
PAPER_FIG := $(foreach c,tc1a_rolling tc1b_sliding tc2_jump tc3_receding,$(foreach m,dynamic repulsive noncohesive noncohesive_spring hertz,$(c)_$(m)))
figures: deps build/mbsph
	@for c in $(PAPER_FIG); do echo "== $$c"; build/mbsph input/paper/$$c.nml > /dev/null || exit 1; done
	$(PYTHON) -m post.paper_cases OUT/paper --out doc/img

paper: figures
	@for m in dynamic repulsive noncohesive noncohesive_spring hertz; do build/mbsph input/paper/tc4_stack_$$m.nml > /dev/null || exit 1; done

# hard cases, long runs (about 15 minutes on one core); each case's exit status is kept
# beside its output (a case may be meant to stop), the verdicts go to doc/stability.md
stability: deps build/mbsph
	@for c in input/stability/*.nml; do n=$$(basename $$c .nml); echo "== $$c"; mkdir -p OUT/stability/$$n; \
	  build/mbsph $$c > /dev/null 2> OUT/stability/$$n/stderr; echo $$? > OUT/stability/$$n/exit_status; done
	$(PYTHON) -m post.stability OUT/stability/* --table doc/stability.md

# accuracy against cost: every study of study/*.toml (resumable: finished runs are
# kept in OUT/study/), its tables into doc/accuracy-cost.md, its figures into doc/img;
# cost = CPU time of each run, which other processes do not inflate;
# `make study STUDIES=study/tank_dp.toml` for one, STUDY_FLAGS="--workers 1" to limit
STUDIES     ?= $(sort $(wildcard study/*.toml))
STUDY_FLAGS ?= --nice 10
# the porous-region cases of doc/porous.md and their table (about 40 s on one core)
# the same breakwater (regular placement) on a porous and on an impermeable core at the
# same numerics (those the pores need), from the settling to BWC_END: the water level in
# the core, the pressure under the armour, the uplift on the units, side by side
# (doc/porous.md, doc/img/breakwater_core.png)
BWC_END ?= 10.0
breakwater_core: deps build/mbsph
	@mkdir -p OUT/breakwater_core
	@for core in porous impermeable; do \
	  sed -e "s/t_end = 1.0/t_end = $(BWC_END)/" -e "s/dt_out = 0.25/dt_out = 0.1/" \
	    -e "s#out_dir = 'OUT/breakwater_regular_porous'#out_dir = 'OUT/breakwater_core/$$core'#" \
	    -e "s/core = 'porous'/core = '$$core'/" input/breakwater/regular_porous.nml > OUT/breakwater_core/$$core.nml; \
	done
	$(MPIRUN) -np 1 build/mbsph OUT/breakwater_core/porous.nml > OUT/breakwater_core/porous.log & \
	$(MPIRUN) -np 1 build/mbsph OUT/breakwater_core/impermeable.nml > OUT/breakwater_core/impermeable.log; \
	wait
	$(PYTHON) -m post.breakwater_core OUT/breakwater_core/porous OUT/breakwater_core/impermeable --t-start 3.5 \
	  --out doc/img/breakwater_core.png --table OUT/breakwater_core/table.md

# regular waves on a rectangular porous breakwater: reflection and transmission against
# Madsen (1974), and the same flume without it for its own decay (doc/porous.md); the
# two runs side by side, one core each. PW_DP: the particle spacing [m]
PW_DP ?= 0.015
porous_waves: deps build/mbsph
	$(PYTHON) -m post.porous_waves --write OUT/porous_waves.nml --dp $(PW_DP)
	$(PYTHON) -m post.porous_waves --write OUT/porous_waves_empty.nml --dp $(PW_DP) --no-structure
	build/mbsph OUT/porous_waves.nml > /dev/null & pid=$$!; \
	  build/mbsph OUT/porous_waves_empty.nml > /dev/null; st=$$?; wait $$pid && test $$st = 0
	$(PYTHON) -m post.porous_waves OUT/porous_waves --empty OUT/porous_waves_empty

porous: deps build/mbsph
	$(PYTHON) -m post.porous_cases --bin build/mbsph --out OUT/porous

study: deps build/mbsph
	$(PYTHON) -m post.study $(STUDIES) --doc doc/accuracy-cost.md --img doc/img --cost cpu_s $(STUDY_FLAGS)

bench: deps build/mbsph build/mbsph3d
	$(PYTHON) bench/run_bench.py

# unused effects cost nothing: the benchmark fluid-only, with a body far from the water,
# and with every optional model on (doc/performance.md#effects-that-are-off);
# BENCH_REF=path/to/mbsph also runs the fluid-only case with another build
bench-effects: deps build/mbsph
	$(PYTHON) bench/run_effects.py $(if $(BENCH_REF),--reference $(BENCH_REF))

# strong and weak scaling on 1 and 2 MPI ranks (doc/performance.md#several-ranks)
bench-mpi: deps build/mbsph
	$(PYTHON) bench/run_mpi.py strong
	$(PYTHON) bench/run_mpi.py weak

clean:
	rm -rf build
