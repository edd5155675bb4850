# Vesuvius — one GNU Makefile. `make help` lists the targets.
#   make            build the libraries and tools into build/ (VIEWER=0: no vsv-play)
#   make test       build and run every test (ends with "N passed, N failed"; checks
#                   that need the large files of ../shared/data say SKIP when absent)
#   make test SAN=1 the same with AddressSanitizer and UBSan (build-san/)
#   make test TSAN=1 the threaded tests with ThreadSanitizer (build-tsan/)
#   make mutate     the mutation harness: tests/mutants/*.patch, score and survivors
#   make demo       install what is missing, build, run the main job on samples/
#   make bench      run the benchmarks in bench/ (results: bench/RESULTS.md)
#   make install    PREFIX=/usr/local DESTDIR= (LIBDIR=PREFIX/lib); make uninstall the same
#   make deb        the Debian packages (debian/) in build/deb/, lintian-checked
#   make test-deb   build them from a clone, install, use and purge them (root)
#   make fuzz       build the libFuzzer targets with clang (build-fuzz/), run each FUZZ_SECONDS
#   MPI=1 / MPI=0 builds vsv-convert-mpi or not (default: when mpicc is found).
#   V=1 for verbose commands, WERROR=1 (default under CI) for -Werror.

PREFIX ?= /usr/local
DESTDIR ?=
BINDIR = $(PREFIX)/bin
LIBDIR = $(PREFIX)/lib
INCDIR = $(PREFIX)/include/vesuvius
MANDIR = $(PREFIX)/share/man

CC ?= cc
CXX ?= c++
PKG_CONFIG ?= pkg-config
SHARED ?= ../shared

PKGS = libzstd geographiclib netcdf libpng OpenEXR freetype2 tbb blosc Imath libcurl epoxy
# OpenVDB (libopenvdb-dev) ships no pkg-config file: its header and -lopenvdb,
# with its own dependencies (tbb, blosc, Imath) through pkg-config above
OPENVDB_LIBS = -lopenvdb
# the plots (render/vsv_plot*.c, vsv-plot) only: PNG, SVG and PDF through cairo
PLOT_PKGS = cairo
# the desktop viewer (vsv-play) only
VIEWER_PKGS = glfw3 gl freetype2 fontconfig
ifeq ($(SAN),1)
  B = build-san
  SANFLAGS = -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all
  OPT = -O1 -g
else ifeq ($(TSAN),1)
  # ThreadSanitizer: `make test TSAN=1` builds and runs the threaded tests only
  B = build-tsan
  SANFLAGS = -fsanitize=thread -fno-omit-frame-pointer
  OPT = -O1 -g
else
  B = build
  SANFLAGS =
  OPT = -O3 -g
endif
WERROR ?= $(if $(CI),1,0)
ifeq ($(WERROR),1)
  WFLAGS_ERR = -Werror
endif

# The dependency step comes first: `make demo` and `make test` run
# tools/deps.sh --install (as root it installs what is missing, otherwise it
# prints the one apt-get line and stops) before anything asks pkg-config.
# Other build goals stop here with that line when a library is missing.
NODEP_GOALS = demo test deps help clean fuzz deb test-deb
ifneq ($(filter-out $(NODEP_GOALS),$(or $(MAKECMDGOALS),all)),)
  MISSING := $(foreach p,$(PKGS) $(PLOT_PKGS),$(if $(shell $(PKG_CONFIG) --exists $(p) 2>/dev/null && echo y),,$(p)))
  ifneq ($(strip $(MISSING)),)
    $(error missing libraries (pkg-config): $(strip $(MISSING)); run `make deps` as root, or: sudo apt-get install -y $(shell sh tools/deps.sh --names))
  endif
endif
# The viewer (vsv-play) is built only where GLFW, GL, FreeType and fontconfig
# are installed; VIEWER=0 leaves it out, and everything else builds and tests
# headless.
VIEWER ?= $(shell $(PKG_CONFIG) --exists $(VIEWER_PKGS) 2>/dev/null && echo 1 || echo 0)

PKG_CFLAGS := $(shell $(PKG_CONFIG) --cflags $(PKGS) 2>/dev/null)
pkglibs = $(shell $(PKG_CONFIG) --libs $(1) 2>/dev/null)
PLOT_CFLAGS := $(shell $(PKG_CONFIG) --cflags $(PLOT_PKGS) 2>/dev/null)
VIEWER_CFLAGS := $(if $(filter 1,$(VIEWER)),$(shell $(PKG_CONFIG) --cflags $(VIEWER_PKGS) 2>/dev/null))
VIEWER_LIBS := $(if $(filter 1,$(VIEWER)),$(shell $(PKG_CONFIG) --libs $(VIEWER_PKGS) 2>/dev/null))

# Truncating text into fixed-size info fields is by design, hence no -Wformat-truncation.
WARN = -Wall -Wextra -Wshadow -Wno-format-truncation $(WFLAGS_ERR)
# INC is each folder's include path (below): a folder sees its own headers
# and those of the layers under it (DESIGN.md §1), so an include against the
# arrows does not compile; XINC adds cli/ for the programs.
CFLAGS_ALL = -std=c11 -D_GNU_SOURCE -fPIC $(OPT) $(WARN) -Wstrict-prototypes $(SANFLAGS) -pthread -MMD -MP \
             $(INC) $(XINC) $(PKG_CFLAGS) $(CPPFLAGS) $(CFLAGS)
CXXFLAGS_ALL = -std=c++17 -fPIC $(OPT) $(WARN) $(SANFLAGS) -pthread -MMD -MP $(INC) $(PKG_CFLAGS) $(CPPFLAGS) $(CXXFLAGS)

ifeq ($(V),1)
  Q =
else
  Q = @
endif

# ------------------------------------------------------------- the layers
# Each library folder is one layer (DESIGN.md §1, "Libraries and programs";
# ARCHITECTURE.md: the arrows as built and decided).
#   common   common/               the internal helpers, under every library
#   core     format/ + stream/     libc, zstd; GeographicLib for projections
#   http     format/http/          core, libcurl: .vsv files read from web servers
#   convert  convert/              core, netCDF
#   render   render/               core, libpng, OpenEXR, FreeType, netCDF (GSHHG outlines)
#   interop  interop/              convert, core, OpenVDB
# cli/ is the programs' own static library (options, JSON, progress, exits):
# no library links it. viewer/ keeps the player core for its programs.
$(B)/common/%.o: INC = -Icommon -Iformat
$(B)/format/%.o: INC = -Iformat -Icommon
$(B)/format/http/%.o: INC = -Iformat/http -Iformat -Icommon
$(B)/stream/%.o: INC = -Istream -Iformat -Icommon
$(B)/convert/%.o: INC = -Iconvert -Iformat -Icommon
$(B)/render/%.o: INC = -Irender -Iformat -Icommon
$(B)/render/gl/%.o: INC = -Irender/gl -Irender -Iformat -Icommon
$(B)/interop/%.o: INC = -Iinterop -Iconvert -Iformat -Icommon
$(B)/cli/%.o: INC = -Icli -Iformat -Icommon
$(B)/viewer/%.o: INC = -Iviewer -Irender/gl -Irender -Istream -Iformat -Icommon -Icli
ALL_INC = -Iformat -Icommon -Istream -Iconvert -Irender -Irender/gl -Iinterop -Iviewer -Icli
$(B)/tests/%.o $(B)/bench/%.o: INC = $(ALL_INC)

objs = $(patsubst %.cc,$(B)/%.o,$(patsubst %.c,$(B)/%.o,$(1)))
# common/: the private helpers the libraries share, as zstd's lib/common/
# (vsv_common.h: bytes, buffers, messages, limits, guarded input, helper
# programs, fd I/O; vsv_vgrid.h: the even-height resampler), compiled once
# into one internal archive. The core's static archive carries them (every
# static link ends with it); each shared library links the archive in
# privately (its version script keeps them local).
COMMON_OBJ = $(call objs,$(wildcard common/vsv_*.c))
COMMON_A = $(B)/common/libvsv-common.a
CORE_OBJ = $(call objs,$(wildcard format/vsv_*.c) $(wildcard format/vsv_*.cc) $(wildcard stream/vsv_*.c)) $(COMMON_OBJ)
# vsv_*_cli.c: program code a folder's tools share (never in a library)
CONVERT_OBJ = $(call objs,$(filter-out %_cli.c,$(wildcard convert/vsv_*.c)))
RENDER_OBJ = $(call objs,$(filter-out %_cli.c,$(wildcard render/vsv_*.c)))
GL_OBJ = $(call objs,$(wildcard render/gl/vsv_*.c))
INTEROP_OBJ = $(call objs,$(wildcard interop/vsv_*.c) $(wildcard interop/vsv_*.cc))
# OpenVDB's calls and the helper's side of them: only the helper program
# vsv-vdb-reader links them (from the archive), so neither a tool nor the
# shared library loads OpenVDB (issue 33)
INTEROP_HELPER_OBJ = $(B)/interop/vsv_vdb.o $(B)/interop/vsv_vdb_helper.o
CLI_OBJ = $(call objs,$(wildcard cli/vsv_*.c))
HTTP_OBJ = $(call objs,$(wildcard format/http/vsv_*.c))
PLAYER_OBJ = $(B)/viewer/vsv_player.o $(B)/viewer/vsv_player_opts.o $(B)/viewer/vsv_player_do.o $(B)/viewer/vsv_player_state.o $(B)/viewer/vsv_player_gl.o $(B)/viewer/vsv_freevr_conf.o \
             $(B)/viewer/vsv_room.o $(B)/viewer/vsv_place.o $(B)/viewer/vsv_wand.o $(B)/viewer/vsv_procs.o

CORE_A = $(B)/libvesuvius.a
CONVERT_A = $(B)/libvesuvius-convert.a
RENDER_A = $(B)/libvesuvius-render.a
GL_A = $(B)/libvesuvius-gl.a
INTEROP_A = $(B)/libvesuvius-interop.a
HTTP_A = $(B)/libvesuvius-http.a
CLI_A = $(B)/cli/libvsv-cli.a
PLAYER_A = $(B)/viewer/libvsv-player.a
LIBS_A = $(CORE_A) $(CONVERT_A) $(RENDER_A) $(GL_A) $(INTEROP_A) $(HTTP_A)

# what each library needs below it (the link lines of programs and of the
# shared libraries)
CORE_EXT = $(call pkglibs,libzstd geographiclib) -lstdc++ -lm -pthread $(SANFLAGS)
CONVERT_EXT = $(call pkglibs,netcdf) $(CORE_EXT)
RENDER_EXT = $(call pkglibs,libpng OpenEXR freetype2) $(CORE_EXT)
# what a program that draws plots (vsv_plot_*) needs besides RENDER_EXT
PLOT_EXT = $(call pkglibs,$(PLOT_PKGS))
# the GPU raycaster: libepoxy, which loads libGL or libEGL when asked
GL_EXT = $(call pkglibs,epoxy) $(RENDER_EXT)
INTEROP_EXT = $(OPENVDB_LIBS) $(call pkglibs,tbb blosc Imath) $(CONVERT_EXT)
HTTP_EXT = $(call pkglibs,libcurl)
ALL_EXT = $(OPENVDB_LIBS) $(call pkglibs,$(PKGS) $(PLOT_PKGS)) -lstdc++ -lm -pthread $(SANFLAGS) $(LDLIBS)

VERSION := $(shell sed -n 's/^\#define VSV_VERSION_STRING "\(.*\)"/\1/p' format/vsv_format.h)
SOVERSION = 0
so = $(B)/lib$(1).so.$(VERSION)
SHLIBS = $(call so,vesuvius) $(call so,vesuvius-convert) $(call so,vesuvius-render) $(call so,vesuvius-gl) $(call so,vesuvius-interop) \
         $(call so,vesuvius-http)
DATADIR = $(PREFIX)/share

TOOLS = vsv-pack vsv-info vsv-extract vsv-interp vsv-convert vsv-render vsv-export vsv-query vsv-plot
ifeq ($(VIEWER),1)
TOOLS += vsv-play
endif
# vsv-convert-mpi: Open MPI (libopenmpi-dev), found through its mpicc wrapper;
# only that program sees MPI, the libraries never do
MPICC ?= mpicc
MPI ?= $(if $(shell command -v $(MPICC) 2>/dev/null),1,0)
ifeq ($(MPI),1)
  MPI_CFLAGS := $(shell $(MPICC) --showme:compile 2>/dev/null)
  MPI_LIBS := $(shell $(MPICC) --showme:link 2>/dev/null)
  TOOLS += vsv-convert-mpi
endif
TOOL_BIN = $(addprefix $(B)/,$(TOOLS))
# private helper programs (common/vsv_helper.c): the libraries exec them to
# read files with a library that can crash on them; beside the tools in the
# build tree, in $(LIBDIR)/vesuvius/ when installed
HELPERS = vsv-nc-check vsv-vdb-reader vsv-nc-writer vsv-gshhg
HELPER_BIN = $(addprefix $(B)/,$(HELPERS))
HELPER_DIR = $(LIBDIR)/vesuvius
# the programs: each sees cli/ besides its folder's layers; vsv-extract,
# vsv-convert and vsv-info read .vdb sequences through interop/
TOOL_OBJ = $(B)/convert/vsv_convert_cli.o $(B)/format/vsv-pack.o $(B)/format/vsv-query.o $(B)/convert/vsv-info.o $(B)/convert/vsv-extract.o $(B)/convert/vsv-interp.o \
           $(B)/convert/vsv-convert.o $(B)/render/vsv-render.o $(B)/render/vsv_movie_cli.o $(B)/interop/vsv-export.o \
           $(B)/render/vsv-plot.o
$(TOOL_OBJ): XINC = -Icli
$(B)/render/vsv-render.o: XINC = -Icli -Irender/gl
$(B)/interop/vsv-export.o: XINC = -Icli -Irender
$(B)/convert/vsv-extract.o $(B)/convert/vsv-convert.o $(B)/convert/vsv-info.o: XINC = -Icli -Iinterop
$(B)/convert/vsv-convert-mpi.o $(B)/convert/vsv_mpi_cli.o: XINC = -Icli -Iinterop $(MPI_CFLAGS)

TEST_SRC = $(wildcard tests/test_*.c)
TEST_BIN = $(patsubst tests/%.c,$(B)/tests/%,$(TEST_SRC))
TEST_HELPERS = $(B)/tests/vsv_refread.o $(B)/tests/vsv_testlib.o $(B)/tests/vsv_synth.o
# the fuzz targets (tests/fuzz_*.c, tests/FUZZING.md): each runs in `make
# test` over its corpus as test_fuzz_NAME, and under libFuzzer in `make fuzz`
FUZZ_TARGETS = vsv mm5 uamiv camxmet netcdf grads stream text player argv
FUZZ_BIN = $(patsubst %,$(B)/tests/test_fuzz_%,$(FUZZ_TARGETS))
# tests and benchmarks are white-box: every library, every dependency
TEST_LIBS = $(PLAYER_A) $(INTEROP_A) $(CONVERT_A) $(GL_A) $(RENDER_A) $(HTTP_A) $(CORE_A) $(CLI_A)

# The Python module `vesuvius` (python/): the CPython and NumPy C APIs from
# Debian's python3-dev and python3-numpy, the library linked in statically.
# Skipped, with a note, where they are missing, and under SAN=1 (an ASan
# build cannot be loaded into a python3 that was not started with it).
PYTHON ?= /usr/bin/python3
PY_INC := $(shell $(PYTHON) -c "import sysconfig; print(sysconfig.get_paths()['include'])" 2>/dev/null)
PY_NUMPY_INC := $(shell $(PYTHON) -c "import numpy; print(numpy.get_include())" 2>/dev/null)
PY_EXT := $(shell $(PYTHON) -c "import sysconfig; print(sysconfig.get_config_var('EXT_SUFFIX'))" 2>/dev/null)
PY_MISSING := $(if $(wildcard $(PY_INC)/Python.h),,python3-dev )$(if $(PY_NUMPY_INC),,python3-numpy)
PY_MISSING := $(if $(strip $(PY_MISSING)),apt-get install $(PY_MISSING))
ifeq ($(SAN),1)
  PY_MISSING := not under SAN=1
endif
ifeq ($(TSAN),1)
  PY_MISSING := not under TSAN=1
endif
ifeq ($(strip $(PY_MISSING)),)
  PYMOD = $(B)/python/vesuvius/_vesuvius$(PY_EXT) $(B)/python/vesuvius/__init__.py
endif
# where that interpreter looks for modules installed under PREFIX, asked of
# it (tools/pydir.py): on Debian /usr/lib/python3/dist-packages for /usr and
# /usr/local/lib/python3.X/dist-packages for /usr/local, both on its path;
# PREFIX/lib/python3.X/site-packages elsewhere (with PYTHONPATH)
PYDIR := $(if $(PYMOD),$(shell $(PYTHON) tools/pydir.py $(PREFIX) 2>/dev/null))

.PHONY: fuzz-bin demo-bin all test test-run mutate demo bench install uninstall clean fuzz help deps freevr freevr-syntax \
  deb test-deb install-freevr
.SECONDARY:
all: $(LIBS_A) $(SHLIBS) $(TOOL_BIN) $(HELPER_BIN) $(PYMOD)
ifneq ($(strip $(PY_MISSING)),)
	@echo "note: the Python module is not built: $(PY_MISSING)"
endif

$(B)/python/vsv_python.o $(B)/python/vsv_python_traj.o $(B)/python/vsv_python_names.o $(B)/python/vsv_python_write.o: $(B)/python/%.o: python/%.c
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  CC      $<")
	$(Q)$(CC) $(CFLAGS_ALL) -I$(PY_INC) -I$(PY_NUMPY_INC) -c $< -o $@

$(B)/python/vsv_python.o $(B)/python/vsv_python_traj.o $(B)/python/vsv_python_names.o $(B)/python/vsv_python_write.o: INC = -Iformat -Icommon
$(B)/python/vesuvius/_vesuvius$(PY_EXT): $(B)/python/vsv_python.o $(B)/python/vsv_python_traj.o $(B)/python/vsv_python_names.o $(B)/python/vsv_python_write.o $(HTTP_A) $(CORE_A)
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) $(LDFLAGS) -shared -o $@ $^ -Wl,--as-needed $(HTTP_EXT) $(CORE_EXT)

$(B)/python/vesuvius/%.py: python/vesuvius/%.py
	@mkdir -p $(dir $@)
	$(Q)cp $< $@

help:
	@sed -n '2,/^#   V=1/p' Makefile | sed 's/^# *//'

$(B)/%.o: %.c
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  CC      $<")
	$(Q)$(CC) $(CFLAGS_ALL) -c $< -o $@

# the raycaster's sixteen-ray march: AVX2 + FMA code, called only on CPUs that have them
$(B)/render/vsv_raycast_simd.o: CFLAGS_ALL += -mavx2 -mfma
$(B)/render/vsv_raycast_avx512.o: CFLAGS_ALL += -mavx2 -mfma -mavx512f
# the plots: cairo's headers for their files only
$(B)/render/vsv_plot%.o: CFLAGS_ALL += $(PLOT_CFLAGS)
# the shear-warp's eight-pixel rows, built for any x86-64 (its eight-float
# vectors never cross a call, so -Wpsabi's ABI note is moot) and for AVX2 + FMA
$(B)/render/vsv_sw_row.o: CFLAGS_ALL += -Wno-psabi
$(B)/render/vsv_sw_row_avx2.o: CFLAGS_ALL += -mavx2 -mfma -mf16c -ffp-contract=fast

$(B)/common/vsv_helper.o: CFLAGS_ALL += -DVSV_HELPER_DIR='"$(HELPER_DIR)"'

$(B)/%.o: %.cc
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  CXX     $<")
	$(Q)$(CXX) $(CXXFLAGS_ALL) -c $< -o $@

# ------------------------------------------------------------- libraries
$(CORE_A): $(CORE_OBJ)
$(COMMON_A): $(COMMON_OBJ)
$(CONVERT_A): $(CONVERT_OBJ)
$(RENDER_A): $(RENDER_OBJ)
$(GL_A): $(GL_OBJ)
$(INTEROP_A): $(INTEROP_OBJ)
$(HTTP_A): $(HTTP_OBJ)
$(CLI_A): $(CLI_OBJ)
$(PLAYER_A): $(PLAYER_OBJ)
$(LIBS_A) $(COMMON_A) $(CLI_A) $(PLAYER_A):
	@$(if $(Q),echo "  AR      $@")
	$(Q)rm -f $@ && ar rcs $@ $^

# shared libraries: versioned file, soname lib*.so.$(SOVERSION); each links
# the one below it and its own dependencies only, and exports exactly the
# vsv_ names its public headers declare: a version script made from them
# (everything else, internals and OpenVDB's template code, stays local)
H_libvesuvius = format/vsv_format.h format/vsv_time.h format/vsv_vector.h format/vsv_output.h format/vsv_traj.h stream/vsv_pager.h stream/vsv_clock.h
H_libvesuvius-convert = convert/vsv_convert.h convert/vsv_source_reader.h
H_libvesuvius-render = render/vsv_render.h
H_libvesuvius-gl = render/gl/vsv_gl.h
H_libvesuvius-interop = interop/vsv_vdb.h interop/vsv_cf.h
H_libvesuvius-http = format/vsv_http.h
$(foreach l,vesuvius vesuvius-convert vesuvius-render vesuvius-gl vesuvius-interop vesuvius-http,$(eval $(B)/lib$(l).map: $(H_lib$(l))))
$(B)/%.map:
	@mkdir -p $(dir $@)
	$(Q){ echo '{ global:'; grep -ho 'vsv_[A-Za-z0-9_]*' $^ | sort -u | sed 's/$$/;/'; echo 'local: *; };'; } > $@
shlib = $(Q)$(CC) $(LDFLAGS) -shared -Wl,-soname,$(patsubst %.$(VERSION),%,$(notdir $@)).$(SOVERSION) \
        -Wl,--version-script=$(patsubst %.so.$(VERSION),%.map,$@) -o $@ $(1)
$(call so,vesuvius): $(B)/libvesuvius.map $(CORE_OBJ)
	@$(if $(Q),echo "  LD      $@")
	$(call shlib,$(filter-out %.map,$^) $(CORE_EXT))
$(call so,vesuvius-convert): $(B)/libvesuvius-convert.map $(CONVERT_OBJ) $(COMMON_A) $(call so,vesuvius)
	@$(if $(Q),echo "  LD      $@")
	$(call shlib,$(filter-out %.map,$^) $(CONVERT_EXT))
$(call so,vesuvius-render): $(B)/libvesuvius-render.map $(RENDER_OBJ) $(COMMON_A) $(call so,vesuvius)
	@$(if $(Q),echo "  LD      $@")
	$(call shlib,$(filter-out %.map,$^) $(PLOT_EXT) $(RENDER_EXT))
$(call so,vesuvius-gl): $(B)/libvesuvius-gl.map $(GL_OBJ) $(call so,vesuvius-render) $(call so,vesuvius)
	@$(if $(Q),echo "  LD      $@")
	$(call shlib,$(filter-out %.map,$^) $(call pkglibs,epoxy))
$(call so,vesuvius-interop): $(B)/libvesuvius-interop.map $(filter-out $(INTEROP_HELPER_OBJ),$(INTEROP_OBJ)) $(COMMON_A) \
                             $(call so,vesuvius-convert) $(call so,vesuvius)
	@$(if $(Q),echo "  LD      $@")
	$(call shlib,$(filter-out %.map,$^) $(INTEROP_EXT))
$(call so,vesuvius-http): $(B)/libvesuvius-http.map $(HTTP_OBJ) $(call so,vesuvius)
	@$(if $(Q),echo "  LD      $@")
	$(call shlib,$(filter-out %.map,$^) $(HTTP_EXT) $(CORE_EXT))

# -------------------------------------------------------------- programs
# each links only the libraries it uses (static archives: the programs stand alone)
link = @$(if $(Q),echo "  LD      $@")
# the programs that read a .vsv read URLs too (format/http/, libcurl)
$(B)/vsv-pack: $(B)/format/vsv-pack.o $(CLI_A) $(CORE_A)
	$(link)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(CORE_EXT)
$(B)/vsv-query: $(B)/format/vsv-query.o $(CLI_A) $(HTTP_A) $(CORE_A)
	$(link)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(HTTP_EXT) $(CORE_EXT)
$(B)/vsv-interp: $(B)/convert/vsv-interp.o $(CLI_A) $(CONVERT_A) $(CORE_A)
	$(link)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(CONVERT_EXT)
$(B)/vsv-info: $(B)/convert/vsv-info.o $(CLI_A) $(INTEROP_A) $(CONVERT_A) $(HTTP_A) $(CORE_A)
	$(link)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(HTTP_EXT) $(INTEROP_EXT)
$(B)/vsv-extract: $(B)/convert/vsv-extract.o $(B)/convert/vsv_convert_cli.o $(CLI_A) $(INTEROP_A) $(CONVERT_A) $(CORE_A)
	$(link)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(INTEROP_EXT)
$(B)/vsv-convert: $(B)/convert/vsv-convert.o $(B)/convert/vsv_convert_cli.o $(CLI_A) $(INTEROP_A) $(CONVERT_A) $(CORE_A)
	$(link)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(INTEROP_EXT)
$(B)/vsv-convert-mpi: $(B)/convert/vsv-convert-mpi.o $(B)/convert/vsv_mpi_cli.o $(B)/convert/vsv_convert_cli.o $(CLI_A) \
                     $(INTEROP_A) $(CONVERT_A) $(CORE_A)
	$(link)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(INTEROP_EXT) $(MPI_LIBS)
$(B)/vsv-export: $(B)/interop/vsv-export.o $(CLI_A) $(INTEROP_A) $(RENDER_A) $(CONVERT_A) $(HTTP_A) $(CORE_A)
	$(link)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(HTTP_EXT) $(INTEROP_EXT) $(RENDER_EXT)
$(B)/vsv-plot: $(B)/render/vsv-plot.o $(CLI_A) $(RENDER_A) $(HTTP_A) $(CORE_A)
	$(link)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(HTTP_EXT) $(PLOT_EXT) $(RENDER_EXT)
$(B)/vsv-render: $(B)/render/vsv-render.o $(B)/render/vsv_movie_cli.o $(CLI_A) $(GL_A) $(RENDER_A) $(HTTP_A) $(CORE_A)
	$(link)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(HTTP_EXT) $(GL_EXT)

$(B)/vsv-nc-check: $(B)/convert/vsv-nc-check.o
	$(link)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(CONVERT_EXT)
$(B)/vsv-gshhg: $(B)/render/vsv-gshhg.o
	$(link)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(call pkglibs,netcdf) -lm $(SANFLAGS)
$(B)/vsv-vdb-reader: $(B)/interop/vsv-vdb-reader.o $(INTEROP_A) $(CONVERT_A) $(CORE_A)
	$(link)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(INTEROP_EXT)
$(B)/vsv-nc-writer: $(B)/interop/vsv-nc-writer.o $(INTEROP_A) $(CONVERT_A) $(CORE_A)
	$(link)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(INTEROP_EXT)

$(B)/viewer/vsv-play.o $(B)/viewer/vsv_overlay.o $(B)/viewer/vsv_panel.o: CFLAGS_ALL += $(VIEWER_CFLAGS)
$(B)/vsv-play: $(B)/viewer/vsv-play.o $(B)/viewer/vsv_overlay.o $(PLAYER_A) $(CLI_A) $(GL_A) $(RENDER_A) $(HTTP_A) $(CORE_A)
	$(link)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(HTTP_EXT) $(GL_EXT) $(VIEWER_LIBS)

# The FreeVR back end: `make FREEVR_DIR=DIR freevr` builds it against a
# FreeVR install (DIR/include/freevr.h, DIR/lib/libfreevr.a; its headers as
# system headers, which -Wstrict-prototypes would reject). `make test` builds
# it against the project's stand-in (tests/freevr-standin/, never installed)
# and checks its syntax against the declarations in viewer/freevr/.
FREEVR_LIBS = -lGL -lX11 -lXi -ldl -lm -lpthread
ifneq ($(FREEVR_DIR),)
TOOLS += vsv-play-freevr
endif
VIEWER_INC = -Iviewer -Irender/gl -Irender -Istream -Iformat -Icommon -Icli
# The libraries it links: this tree's archives, or with VSV_LIBDIR=DIR those
# of an installed libvesuvius-dev of the same version (DIR: `pkg-config
# --variable=libdir vesuvius`; the Debian package's). The player core and
# cli/ are the programs' own, never installed: compiled here either way.
ifneq ($(VSV_LIBDIR),)
  FREEVR_VSV_A = $(addprefix $(VSV_LIBDIR)/,libvesuvius-gl.a libvesuvius-render.a libvesuvius-http.a libvesuvius.a)
else
  FREEVR_VSV_A = $(GL_A) $(RENDER_A) $(HTTP_A) $(CORE_A)
endif
# $(call freevr_link,OUTPUT,FREEVR-DIR)
define freevr_link
	@mkdir -p $(dir $(1))
	@$(if $(Q),echo "  CC/LD   $(1)")
	$(Q)$(CC) $(CFLAGS_ALL) $(VIEWER_INC) $(VIEWER_CFLAGS) -isystem $(2)/include $(LDFLAGS) -o $(1) $(FREEVR_SRC) \
	  $(B)/viewer/vsv_overlay.o $(B)/viewer/vsv_panel.o $(PLAYER_A) $(CLI_A) $(FREEVR_VSV_A) $(2)/lib/libfreevr.a $(HTTP_EXT) $(GL_EXT) \
	  $(VIEWER_LIBS) $(FREEVR_LIBS)
endef
# the back end's two halves: the main process and the render processes
FREEVR_SRC = viewer/vsv-play-freevr.c viewer/vsv_freevr_draw.c
FREEVR_DEPS = $(FREEVR_SRC) viewer/vsv_freevr_app.h $(B)/viewer/vsv_overlay.o $(B)/viewer/vsv_panel.o $(PLAYER_A) $(CLI_A) $(FREEVR_VSV_A)
freevr: $(B)/vsv-play-freevr
$(B)/vsv-play-freevr: $(FREEVR_DEPS)
	@test -n "$(FREEVR_DIR)" || { echo "vsv-play-freevr needs FreeVR: make FREEVR_DIR=DIR freevr" \
	  "(DIR/include/freevr.h, DIR/lib/libfreevr.a)" >&2; exit 2; }
	@test -f "$(FREEVR_DIR)/include/freevr.h" -a -f "$(FREEVR_DIR)/lib/libfreevr.a" || { echo "FREEVR_DIR=$(FREEVR_DIR):" \
	  "no include/freevr.h or lib/libfreevr.a there" >&2; exit 2; }
	@test -z "$(VSV_LIBDIR)" || { v=$$(sed -n 's/^Version: //p' "$(VSV_LIBDIR)/pkgconfig/vesuvius.pc" 2>/dev/null); \
	  test "$$v" = "$(VERSION)" || { echo "VSV_LIBDIR=$(VSV_LIBDIR) holds Vesuvius '$$v', this tree is $(VERSION):" \
	  "build the back end from the source of the installed version" >&2; exit 2; }; }
	$(call freevr_link,$@,$(FREEVR_DIR))
# the back end alone into PREFIX (beside a packaged Vesuvius: /usr/local)
install-freevr: $(B)/vsv-play-freevr
	install -d $(DESTDIR)$(BINDIR) $(DESTDIR)$(MANDIR)/man1 $(DESTDIR)$(DATADIR)/bash-completion/completions
	install -m 755 $(B)/vsv-play-freevr $(DESTDIR)$(BINDIR)/
	install -m 644 man/vsv-play-freevr.1 $(DESTDIR)$(MANDIR)/man1/
	install -m 644 tools/completion/vesuvius.bash $(DESTDIR)$(DATADIR)/bash-completion/completions/vsv-play-freevr

# the stand-in: FreeVR's calls and conventions (../shared/docs/FREEVR.md)
# written by the project for tests, laid out like an install
STANDIN = $(B)/tests/freevr-standin
STANDIN_OBJ = $(call objs,$(wildcard tests/freevr-standin/freevr_*.c))
$(STANDIN_OBJ): CFLAGS_ALL += -isystem viewer/freevr
$(STANDIN)/include/freevr.h: viewer/freevr/freevr.h
	@mkdir -p $(dir $@)
	$(Q)cp $< $@
$(STANDIN)/lib/libfreevr.a: $(STANDIN_OBJ)
	@mkdir -p $(dir $@)
	$(Q)rm -f $@ && ar rcs $@ $^
$(B)/tests/vsv-play-freevr: $(FREEVR_DEPS) $(STANDIN)/include/freevr.h $(STANDIN)/lib/libfreevr.a
	$(call freevr_link,$@,$(STANDIN))
# a small FreeVR program that exercises the stand-in alone, for the checks
# by hand in tests/freevr-standin/README-checks.txt (not part of make test)
$(STANDIN)/selftest: tests/freevr-standin/standin_selftest.c $(STANDIN)/include/freevr.h $(STANDIN)/lib/libfreevr.a
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  CC/LD   $@")
	$(Q)$(CC) $(filter-out -MMD -MP,$(CFLAGS_ALL)) -isystem $(STANDIN)/include -Itests/freevr-standin -o $@ $< \
	  $(STANDIN)/lib/libfreevr.a -lGL -lX11 -lm
# the back end and its stand-in need the viewer's libraries
FREEVR_TEST = $(if $(filter 1,$(VIEWER)),$(B)/tests/vsv-play-freevr)

# syntax only, no dependency file (it would land in the source tree)
freevr-syntax:
	$(Q)$(CC) $(filter-out -MMD -MP,$(CFLAGS_ALL)) $(VIEWER_INC) $(VIEWER_CFLAGS) -isystem viewer/freevr -fsyntax-only \
	  $(FREEVR_SRC)

# ----------------------------------------------------------------- tests
$(B)/tests/test_%: $(B)/tests/test_%.o $(TEST_HELPERS) $(TEST_LIBS)
	$(link)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(ALL_EXT)

$(B)/tests/mm5crop: $(B)/tests/mm5_crop.o $(TEST_LIBS)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(ALL_EXT)

# a .vsv with a known wind (tests/cli_traj.sh, cli_flow.sh, cli_freevr_room.sh)
$(B)/tests/windfile: $(B)/tests/wind_file.o $(TEST_HELPERS) $(TEST_LIBS)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(ALL_EXT)

# the test shim that truncates a file right after a tool maps it (no
# sanitizer: it is preloaded into sanitized programs)
$(B)/tests/libcutmap.so: tests/cut_preload.c
	@mkdir -p $(dir $@)
	$(Q)$(CC) -std=c11 -D_GNU_SOURCE -O1 -fPIC -shared $(WARN) -o $@ $< -ldl

# the test shim that stops a tool right after it made its temporary output
# (tests/cli_mpi.sh signals it there)
$(B)/tests/libholdtmp.so: tests/hold_preload.c
	@mkdir -p $(dir $@)
	$(Q)$(CC) -std=c11 -D_GNU_SOURCE -O1 -fPIC -shared $(WARN) -o $@ $< -ldl

# cuts a netCDF file by time (the multi-file WRF run of tests/cli_mpi.sh)
$(B)/tests/ncsplit: $(B)/tests/nc_split.o
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(ALL_EXT)

$(B)/tests/test_fuzz_%: $(B)/tests/fuzz_%.o $(B)/tests/fuzz_main.o $(B)/tests/fuzz_source.o $(TEST_HELPERS) $(TEST_LIBS)
	$(link)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(ALL_EXT)

# the argv target (tests/fuzz_argv.c): each tool's main compiled again as
# vsv_fuzz_main_<tool>, all linked into one program; exit, atexit, the
# spawns and the opens of what a tool holds are wrapped (fuzz_argv_rt.c)
ARGV_TOOLS = format/vsv-pack format/vsv-query convert/vsv-info convert/vsv-extract convert/vsv-interp \
             convert/vsv-convert interop/vsv-export render/vsv-render render/vsv-plot
ARGV_OBJ = $(patsubst %,$(B)/tests/argv/%.o,$(ARGV_TOOLS)) $(B)/convert/vsv_convert_cli.o $(B)/render/vsv_movie_cli.o \
           $(B)/tests/fuzz_argv_rt.o $(B)/cli/vsv_cli_http.o
ARGV_WRAP = $(addprefix -Wl$(comma)--wrap=,exit atexit fopen fdopen fclose posix_spawn posix_spawnp vsv_file_open_any \
            vsv_file_free vsv_run_open vsv_run_free vsv_source_open vsv_source_free vsv_renderer_create vsv_renderer_free \
            vsv_gl_context_create vsv_output_temp)
comma = ,
# GCC reasons about main's arguments less once it is not main: vsv-export's
# (checked) step count then looks like it may be negative
ARGV_CFLAGS = -Wno-alloc-size-larger-than
$(B)/tests/argv/%.o: %.c
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  CC      $< (argv fuzz)")
	$(Q)$(CC) $(CFLAGS_ALL) $(ARGV_CFLAGS) -Dmain=vsv_fuzz_main_$(subst -,_,$(notdir $*)) -c $< -o $@
$(B)/tests/test_fuzz_argv: $(B)/tests/fuzz_argv.o $(B)/tests/fuzz_main.o $(B)/tests/fuzz_source.o $(ARGV_OBJ) $(TEST_HELPERS) \
                           $(TEST_LIBS)
	$(link)
	$(Q)$(CC) $(LDFLAGS) $(ARGV_WRAP) -o $@ $^ $(ALL_EXT)

# the mutation harness: each patch of tests/mutants/ applied alone to a
# scratch copy, rebuilt, and the tests it names run (tests/mutate.sh)
mutate: all
	$(Q)B=$(B) SHARED=$(SHARED) PYTHON=$(PYTHON) sh tests/mutate.sh

# `make test` and `make demo` run the dependency step first (see above),
# then build and run in a second make that can ask pkg-config.
test:
	$(Q)sh tools/deps.sh --install-test
	$(Q)$(MAKE) --no-print-directory test-run

ifeq ($(TSAN),1)
# the tests whose code runs threads: the writer's encoders (and an
# abandoned writer's), the pager, the render pool, the player, advection,
# isosurfaces (extracted on the pool);
# any data race or lock-order inversion ThreadSanitizer sees is a failure
# (they run the tools too)
TSAN_TESTS = test_format test_format_damage test_stream test_pager_play test_pager_io test_render test_render_sw test_viewer \
  test_room test_advect test_picture test_iso test_iso_draw
test-run: $(TOOL_BIN) $(patsubst %,$(B)/tests/%,$(TSAN_TESTS))
	$(Q)B=$(B) SHARED=$(SHARED) TESTS="$(TSAN_TESTS)" NOASLR=1 \
	  TSAN_OPTIONS="halt_on_error=1 exitcode=66 second_deadlock_stack=1 $(TSAN_OPTIONS)" sh tests/run.sh
else
test-run: all $(TEST_BIN) $(FUZZ_BIN) $(B)/tests/mm5crop $(B)/tests/windfile $(B)/tests/ncsplit $(B)/tests/libcutmap.so $(B)/tests/libholdtmp.so $(FREEVR_TEST)
	$(Q)B=$(B) SHARED=$(SHARED) SANFLAGS="$(SANFLAGS)" VIEWER=$(VIEWER) \
	  PYTHON=$(PYTHON) PYMOD="$(PYMOD)" PY_MISSING="$(PY_MISSING)" sh tests/run.sh
endif

# The demo: install what is missing (or print the apt-get line), build, then
# run the main job on the bundled sample.
demo:
	$(Q)sh tools/deps.sh --install
	$(Q)$(MAKE) --no-print-directory all demo-bin
	$(Q)B=$(B) sh tools/demo.sh

# what the demo needs beyond `all`, decided by the sub-make above, which sees
# the packages deps.sh has just installed (this make was parsed before them)
demo-bin: $(FREEVR_TEST)

BENCH_BIN = $(B)/bench/bench_rc_peer $(B)/bench/bench_format $(B)/bench/bench_camx $(B)/bench/bench_camx_nc $(B)/bench/bench_render \
            $(B)/bench/bench_play $(B)/bench/bench_advect $(B)/bench/bench_native $(B)/bench/bench_gl $(B)/bench/bench_plot \
            $(B)/bench/bench_iso $(B)/bench/bench_traj $(B)/bench/bench_tubes
$(B)/bench/%: $(B)/bench/%.o $(TEST_LIBS)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(ALL_EXT)

# VolPack and the shear-warp set up alike (bench/vp_match.h)
$(B)/bench/bench_volpack: $(B)/bench/bench_volpack.o $(B)/bench/vp_match.o $(B)/bench/bench_stats.o $(TEST_LIBS)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(ALL_EXT) -lvolpack
$(B)/bench/bench_classify: $(B)/bench/bench_classify.o $(B)/bench/vp_match.o $(B)/bench/bench_stats.o $(TEST_LIBS)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(ALL_EXT) -lvolpack
$(B)/bench/bench_tubes: $(B)/bench/bench_tubes.o $(B)/bench/bench_stats.o $(TEST_LIBS)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(ALL_EXT)
$(B)/bench/bench_codec $(B)/bench/bench_size: $(B)/bench/%: $(B)/bench/%.o $(B)/bench/bench_data.o $(TEST_LIBS)
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(ALL_EXT) -lzfp

bench: all $(BENCH_BIN)
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_format.sh
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_convert.sh
	$(Q)B=$(B) sh bench/bench_camx.sh
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_advect.sh
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_mpi.sh
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_render.sh
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_native.sh
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_plot.sh
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_iso.sh
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_traj.sh
	$(Q)$(B)/bench/bench_tubes
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_play.sh
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_play_real.sh || echo "(the real player's x8 skipped)"
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_http.sh
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_vdb.sh
	$(Q)B=$(B) SHARED=$(SHARED) sh bench/bench_vtk.sh || echo "(VTK comparison skipped)"
	$(Q)if [ -f /usr/include/volpack.h ]; then $(MAKE) --no-print-directory $(B)/bench/bench_volpack && \
	  B=$(B) SHARED=$(SHARED) sh bench/bench_volpack.sh; else echo "(VolPack comparison skipped: apt-get install libvolpack1-dev)"; fi
	$(Q)if [ -f /usr/include/volpack.h ]; then $(MAKE) --no-print-directory $(B)/bench/bench_classify && \
	  B=$(B) SHARED=$(SHARED) sh bench/bench_classify.sh; else echo "(classification vs VolPack skipped: apt-get install libvolpack1-dev)"; fi
	$(Q)if [ -f /usr/include/zfp.h ]; then $(MAKE) --no-print-directory $(B)/bench/bench_codec $(B)/bench/bench_size && \
	  B=$(B) SHARED=$(SHARED) sh bench/bench_codec.sh && B=$(B) SHARED=$(SHARED) sh bench/bench_size.sh; \
	  else echo "(brick coding vs ZFP and CF packing skipped: apt-get install libzfp-dev)"; fi

deps:
	$(Q)sh tools/deps.sh --install

# `make deb`: the Debian packages of debian/, built by dpkg-buildpackage
# from a copy of this tree and written to build/deb/, then lintian
# (tools/deb.sh; it installs what it needs first, as root). `make
# test-deb`: on a fresh clone, make deb, install the packages with apt-get,
# use them from /, purge them; and make install PREFIX=/usr/local for
# python3 (tests/cli_deb.sh; root, changes the system, run by CI); its
# tally at the end, and a FAIL fails the goal
deb:
	$(Q)B=$(B) sh tools/deb.sh
test-deb:
	$(Q)mkdir -p $(B) && { B=$(B) SHARED=$(SHARED) sh tests/cli_deb.sh; echo $$? > $(B)/test-deb.rc; } 2>&1 | \
	  tee $(B)/test-deb.log; \
	  echo "$$(grep -c '^PASS' $(B)/test-deb.log) passed, $$(grep -c '^FAIL' $(B)/test-deb.log) failed"; \
	  [ "$$(cat $(B)/test-deb.rc)" = 0 ] && ! grep -q '^FAIL' $(B)/test-deb.log

# `make fuzz`: every target built with clang's libFuzzer, ASan and UBSan
# (build-fuzz/), then run FUZZ_SECONDS each from its seed corpus
# (tests/fuzz.sh prints executions, coverage and any crash). FUZZ=NAME...
# runs only those. Needs clang (tools/deps.sh --install-fuzz installs it).
FUZZ_SECONDS ?= 60
FUZZ ?= $(FUZZ_TARGETS)
FUZZ_MAKE = B=build-fuzz CC=clang CXX=clang++ OPT="-O1 -g" VIEWER=0 MPI=0 \
  WARN="-Wall -Wextra -Wshadow -Wno-unknown-warning-option $(WFLAGS_ERR)" \
  SANFLAGS="-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all"
FUZZ_LIBS = $(PLAYER_A) $(CONVERT_A) $(GL_A) $(RENDER_A) $(HTTP_A) $(CORE_A) $(CLI_A)
fuzz:
	$(Q)sh tools/deps.sh --install-fuzz
	$(Q)$(MAKE) --no-print-directory $(FUZZ_MAKE) fuzz-bin
	$(Q)FUZZ_SECONDS=$(FUZZ_SECONDS) sh tests/fuzz.sh $(FUZZ)

fuzz-bin: $(patsubst %,$(B)/fuzz/fuzz_%,$(FUZZ))
$(B)/fuzz/fuzz_%: $(B)/tests/fuzz_%.o $(B)/tests/fuzz_source.o $(FUZZ_LIBS)
	@mkdir -p $(dir $@)
	$(link)
	$(Q)$(CC) $(LDFLAGS) -fsanitize=fuzzer -o $@ $^ $(HTTP_EXT) $(RENDER_EXT) $(CONVERT_EXT)
$(B)/fuzz/fuzz_argv: $(B)/tests/fuzz_argv.o $(B)/tests/fuzz_source.o $(ARGV_OBJ) $(INTEROP_A) $(FUZZ_LIBS)
	@mkdir -p $(dir $@)
	$(link)
	$(Q)$(CC) $(LDFLAGS) -fsanitize=fuzzer $(ARGV_WRAP) -o $@ $^ $(ALL_EXT)

# Installed: each library (static, shared with its soname, a pkg-config file)
# and its public headers under include/vesuvius/ (`#include <vesuvius/vsv_format.h>`,
# `pkg-config --cflags --libs vesuvius`).
PUBLIC_H = format/vsv_format.h format/vsv_time.h format/vsv_vector.h format/vsv_output.h format/vsv_traj.h stream/vsv_pager.h stream/vsv_clock.h convert/vsv_convert.h convert/vsv_source_reader.h \
           render/vsv_render.h render/vsv_flow.h render/gl/vsv_gl.h interop/vsv_vdb.h interop/vsv_cf.h format/vsv_http.h
PC_LIBS = vesuvius vesuvius-convert vesuvius-render vesuvius-gl vesuvius-interop vesuvius-http
pc_desc_vesuvius = The .vsv format (writer, reader, field stream, queries, projections) and the streaming pager
pc_req_vesuvius =
pc_reqp_vesuvius = libzstd geographiclib
pc_libsp_vesuvius = -lstdc++ -lm -pthread
pc_desc_vesuvius-convert = Vesuvius model readers (MM5, CAMx, WRF, IOAPI, GrADS) and time interpolation
pc_req_vesuvius-convert = vesuvius
pc_reqp_vesuvius-convert = netcdf
pc_libsp_vesuvius-convert = -lm
pc_desc_vesuvius-render = Vesuvius raycaster and shear-warp renderers, annotation, plots, PNG and EXR output
pc_req_vesuvius-render = vesuvius
pc_reqp_vesuvius-render = libpng OpenEXR freetype2 cairo
pc_libsp_vesuvius-render = -lm -pthread
pc_desc_vesuvius-gl = Vesuvius GPU raycaster (OpenGL 3.3, headless through EGL)
pc_req_vesuvius-gl = vesuvius-render vesuvius
pc_reqp_vesuvius-gl = epoxy
pc_libsp_vesuvius-gl =
pc_desc_vesuvius-interop = Vesuvius volumes to and from OpenVDB, and out as CF netCDF
pc_req_vesuvius-interop = vesuvius-convert vesuvius
pc_reqp_vesuvius-interop = tbb blosc Imath
pc_libsp_vesuvius-interop = $(OPENVDB_LIBS) -lstdc++
pc_desc_vesuvius-http = .vsv files read from web servers (HTTP range requests, an on-disk cache)
pc_req_vesuvius-http = vesuvius
pc_reqp_vesuvius-http = libcurl
pc_libsp_vesuvius-http =

# the .pc files' libdir, relative to ${exec_prefix} when under PREFIX (a
# Debian build sets LIBDIR=/usr/lib/<multiarch triplet>)
PC_LIBDIR = $(patsubst $(PREFIX)/%,$${exec_prefix}/%,$(LIBDIR))

install: all
	@test -z "$(PYMOD)" -o -n "$(PYDIR)" || { echo "no Python module folder for PREFIX=$(PREFIX)" \
	  "($(PYTHON) tools/pydir.py $(PREFIX) failed)" >&2; exit 2; }
	install -d $(DESTDIR)$(BINDIR) $(DESTDIR)$(LIBDIR)/pkgconfig $(DESTDIR)$(INCDIR) $(DESTDIR)$(MANDIR)/man1 \
	  $(DESTDIR)$(MANDIR)/man5 $(DESTDIR)$(DATADIR)/vesuvius $(DESTDIR)$(DATADIR)/bash-completion/completions
	install -m 755 $(TOOL_BIN) $(DESTDIR)$(BINDIR)/
	install -d $(DESTDIR)$(HELPER_DIR)
	install -m 755 $(HELPER_BIN) $(DESTDIR)$(HELPER_DIR)/
	install -m 644 $(LIBS_A) $(DESTDIR)$(LIBDIR)/
	install -m 755 $(SHLIBS) $(DESTDIR)$(LIBDIR)/
	$(foreach l,$(PC_LIBS),ln -sf lib$(l).so.$(VERSION) $(DESTDIR)$(LIBDIR)/lib$(l).so.$(SOVERSION) && \
	  ln -sf lib$(l).so.$(SOVERSION) $(DESTDIR)$(LIBDIR)/lib$(l).so && \
	  sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@LIBDIR@|$(PC_LIBDIR)|' -e 's|@VERSION@|$(VERSION)|' -e 's|@NAME@|$(l)|' -e 's|@DESC@|$(pc_desc_$(l))|' \
	    -e 's|@REQUIRES@|$(pc_req_$(l))|' -e 's|@REQUIRES_PRIVATE@|$(pc_reqp_$(l))|' -e 's|@LIBS_PRIVATE@|$(pc_libsp_$(l))|' \
	    tools/vesuvius.pc.in > $(DESTDIR)$(LIBDIR)/pkgconfig/$(l).pc;)
	install -m 644 $(PUBLIC_H) $(DESTDIR)$(INCDIR)/
	install -m 644 $(filter-out $(if $(FREEVR_DIR),,man/vsv-play-freevr.1),$(wildcard man/*.1)) $(DESTDIR)$(MANDIR)/man1/
	install -m 644 man/*.5 $(DESTDIR)$(MANDIR)/man5/
	install -m 644 share/transfer-functions.tf $(DESTDIR)$(DATADIR)/vesuvius/
	if [ -n "$(PYMOD)" ]; then install -d $(DESTDIR)$(PYDIR)/vesuvius && install -m 644 $(PYMOD) $(DESTDIR)$(PYDIR)/vesuvius/; fi
	for t in $(TOOLS); do install -m 644 tools/completion/vesuvius.bash $(DESTDIR)$(DATADIR)/bash-completion/completions/$$t; done

uninstall:
	rm -f $(addprefix $(DESTDIR)$(BINDIR)/,$(TOOLS))
	rm -rf $(DESTDIR)$(HELPER_DIR)
	rm -f $(foreach l,$(PC_LIBS),$(DESTDIR)$(LIBDIR)/lib$(l).a $(DESTDIR)$(LIBDIR)/lib$(l).so* $(DESTDIR)$(LIBDIR)/pkgconfig/$(l).pc)
	rm -f $(addprefix $(DESTDIR)$(DATADIR)/bash-completion/completions/,$(TOOLS))
	rm -f $(addprefix $(DESTDIR)$(MANDIR)/man1/,$(addsuffix .1,$(TOOLS))) $(DESTDIR)$(MANDIR)/man5/vsv.5
	rm -rf $(DESTDIR)$(INCDIR) $(DESTDIR)$(DATADIR)/vesuvius
	$(if $(PYDIR),rm -rf $(DESTDIR)$(PYDIR)/vesuvius)

clean:
	rm -rf build build-san build-tsan build-fuzz

-include $(shell find $(B) -name '*.d' 2>/dev/null)
