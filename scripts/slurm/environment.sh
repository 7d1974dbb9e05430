# Sourced by the SLURM jobs of this folder, from the repository root ($SLURM_SUBMIT_DIR):
# the site's modules, then a check that everything the job calls is there (one line naming
# what is missing), then the repository root as the working directory and one thread per rank.
# The job sets NEEDS (the commands it calls) before sourcing this; PYTHON names its Python.

# Software, site by site (`module avail petsc` shows yours): the same stack bin/fsiopt was
# built with. MODULES is loaded after a `module purge` (empty: use the job's environment as
# it is); override at submission: sbatch --export=ALL,MODULES="gcc/12 openmpi/4 ..." ...
# e.g. MODULES="gcc/12.2.0 openmpi/4.1.5 petsc/3.18.5 hdf5/1.12.2 gmsh/4.11.1 python/3.11"
#      (the MPI PETSc was built with, with srun's PMI; PETSc with MUMPS)
MODULES=${MODULES:-""}
PYTHON=${PYTHON:-python3}

if [ -n "$MODULES" ]; then
    type module >/dev/null 2>&1 || { echo "MODULES is set but this shell has no 'module' command" >&2; exit 1; }
    module purge
    for m in $MODULES; do
        module load "$m" || { echo "module load $m failed: fix MODULES (scripts/slurm/environment.sh)" >&2; exit 1; }
    done
fi

missing=""
for c in $NEEDS; do command -v "$c" >/dev/null 2>&1 || missing="$missing $c"; done
case " $NEEDS " in
*" $PYTHON "*) "$PYTHON" -c "import numpy, matplotlib" 2>/dev/null || missing="$missing $PYTHON-with-numpy-and-matplotlib" ;;
esac
if [ -x "${SLURM_SUBMIT_DIR:-.}/bin/fsiopt" ]; then
    libs=$(ldd "${SLURM_SUBMIT_DIR:-.}/bin/fsiopt" | awk '/not found/ {print $1}' | tr '\n' ' ')
    [ -z "$libs" ] || missing="$missing libraries-of-bin/fsiopt:(${libs% })"
fi
if [ -n "$missing" ]; then
    echo "missing on $(hostname):$missing (load them with MODULES: scripts/slurm/environment.sh)" >&2
    exit 1
fi

# sbatch starts in the submit directory already; cd makes it explicit (bin/, options/, out/
# are relative to the repository root).
cd "${SLURM_SUBMIT_DIR:-.}"

# One thread per rank: ranks already fill the cores; threaded BLAS would oversubscribe them.
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1

# Nothing is built here: compute nodes often lack compilers or headers. Run `make` on a
# login node (same modules) before submitting.
test -x bin/fsiopt || { echo "bin/fsiopt missing: run make before submitting" >&2; exit 1; }
