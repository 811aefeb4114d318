// The communicator of an ensemble: MPI's world when cavesim was built with MPI and started by
// mpirun, else one process. MPI is initialised only then, funnelled (only the main thread calls
// MPI: the members' threads never do), and finalised at exit.
#include <cstdlib>

#include "app/ensemble.h"
#include "core/error.h"

#ifdef CAVESIM_HAVE_MPI
#include <mpi.h>
#endif

namespace cavesim::app {
namespace {

/// Whether a process manager started this process as part of a job (OpenMPI, MPICH/Hydra, PMIx).
bool launchedByMpirun() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
        if (std::getenv(v)) return true;
    return false;
}

#ifdef CAVESIM_HAVE_MPI
void finalizeMpi() {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized) MPI_Finalize();
}
#endif

}  // namespace

bool mpiAvailable() {
#ifdef CAVESIM_HAVE_MPI
    return true;
#else
    return false;
#endif
}

Communicator processCommunicator() {
    Communicator c;
#ifdef CAVESIM_HAVE_MPI
    if (!launchedByMpirun()) return c;
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (!initialised) {
        int provided = 0;
        if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
            throw RuntimeError("MPI_Init_thread failed");
        std::atexit(finalizeMpi);
    }
    MPI_Comm_rank(MPI_COMM_WORLD, &c.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &c.size);
    MPI_Comm node;  // the ranks that share this machine's memory (and cores)
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, c.rank, MPI_INFO_NULL, &node);
    MPI_Comm_size(node, &c.localRanks);
    MPI_Comm_free(&node);
    c.barrier = [] { MPI_Barrier(MPI_COMM_WORLD); };
#else
    if (launchedByMpirun())
        throw InputError(
            "started by mpirun, but this cavesim was built without MPI (install libopenmpi-dev and "
            "rebuild); every rank would run every member");
#endif
    return c;
}

}  // namespace cavesim::app
