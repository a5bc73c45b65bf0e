/* api_thr.c: pcdm_triangulate with worker threads (include/pcdm.h, pcdm_options.threads >= 1)
 * -- the subdomain mesher of ./pcdm (PCDM, TR-97-17 section 3, refined in rounds) in the
 * calling process, the same mesh as ./pcdm --threads T for every T.
 *
 * It is pcdm_triangulate_par on a one-rank communicator (MPI_COMM_SELF): one process, T worker
 * threads of the runtime refining the subdomains, the calling thread the runtime's main thread.
 * Compiled twice: into libpcdm against MPI (the caller must then have initialised MPI with
 * MPI_THREAD_FUNNELED), and into the MPI-free build (libpcdm_threads, the Python package's threaded
 * path) against the one-process stand-in runtime/mpi1, where MPI is always there and nothing leaves
 * the process.
 *
 * The runtime is one per process (rt_init_comm refuses a second), so threaded calls are
 * serialised by a process-wide lock: a caller waits for the one before it instead of failing.
 * The one rank's part (root < 0: nothing gathered) is the whole mesh in global numbering, the
 * order ./pcdm writes; it is returned as pcdm_triangulate returns a mesh (pointglobal,
 * pointowned dropped).  Invariants: every failure the parallel call reports (bad input,
 * bounds it cannot meet, a mesh it cannot check) comes back as a code and a message, the
 * runtime finalised.
 */
#include "api/api_impl.h"
#include "pcdm_par.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

/* The process's one runtime (see above): held across a threaded call. */
static pthread_mutex_t runtime_lock = PTHREAD_MUTEX_INITIALIZER;

/* The one rank's part m made the whole mesh as pcdm_triangulate returns one: with one rank
 * every point is numbered and the rows are already in global order (the input points, then
 * the others in local order: par_number_open), so pointglobal is the identity and is dropped
 * with pointowned.  Returns 0, or -1 when the part is not that (a bug). */
static int whole_from_part(pcdm_mesh *m) {
    if (m->nglobalpoints != m->npoints || m->nglobaltriangles != m->ntriangles ||
        m->nglobalsegments != m->nsegments || m->trianglefirst != 0)
        return -1;
    for (int32_t i = 0; i < m->npoints; i++)
        if (m->pointglobal[i] != i || !m->pointowned[i]) return -1;
    free(m->pointglobal);
    free(m->pointowned);
    m->pointglobal = NULL;
    m->pointowned = NULL;
    return 0;
}

int api_triangulate_threads(const pcdm_input *in, const pcdm_options *o, pcdm_mesh *out,
                            pcdm_status *st) {
    if (o->region_attributes || o->region_areas)
        return api_fail(st, PCDM_EINVAL,
                        "threads %d: region_attributes and region_areas work with threads 0 only "
                        "(the subdomain mesher does not label regions yet)",
                        o->threads);
    if (o->lenses)
        return api_fail(st, PCDM_EINVAL,
                        "threads %d: lenses work with threads 0 only (the subdomain mesher "
                        "tests diametral circles)",
                        o->threads);
    int inited = 0, fin = 0;
    MPI_Initialized(&inited);
    MPI_Finalized(&fin);
    if (!inited || fin)
        return api_fail(st, PCDM_EMPI,
                        "threads %d: this library (libpcdm, built with MPI) runs threads on "
                        "MPI_COMM_SELF and needs MPI initialised (MPI_Init_thread, "
                        "MPI_THREAD_FUNNELED); libpcdm_threads needs no MPI",
                        o->threads);
    /* the input as the sequential call loads it, so bad input gets the message threads 0
     * gives (the parallel load would say the same, but in the decomposition's words) */
    pslg g;
    if (api_make_pslg(in, o, &g, st) != PCDM_OK) {
        st->code = PCDM_EINPUT;
        memmove(st->message, api_unpath(st->message), strlen(api_unpath(st->message)) + 1);
        return st->code;
    }
    pslg_free(&g);
    pcdm_options p = *o;
    p.method = PCDM_METHOD_PCDM;
    p.root = -1; /* one rank's part is the whole mesh: no gather (its copies, its size limit) */
    pthread_mutex_lock(&runtime_lock);
    int rc = pcdm_triangulate_par(MPI_COMM_SELF, in, &p, out, st);
    pthread_mutex_unlock(&runtime_lock);
    if (rc == PCDM_OK || rc == PCDM_ESTEINER) {
        int code = st->code;
        if (whole_from_part(out) != 0) {
            pcdm_mesh_free(out);
            return api_fail(st, PCDM_EMESH, "the one-rank part is not the whole mesh (a bug)");
        }
        st->code = code;
    }
    return rc;
}
