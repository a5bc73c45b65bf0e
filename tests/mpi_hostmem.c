// ranks: 1 2 4 8
/* mpi_hostmem: Check suite for the block a host's ranks share (mesher/base/hostmem.c).
 *
 *  - every rank maps a block of the asked size, exactly one rank per host leads it, and what
 *    the leader wrote before the seal is what every rank of the host reads after it;
 *  - after the seal the mapping is read-only on every rank (its line in /proc/self/maps), so a
 *    write would fault instead of changing another rank's data;
 *  - holds() answers for the block's first and last byte and not for one past its end;
 *  - nothing is left under /dev/shm once every rank has mapped it.
 * Results are reduced over ranks before asserting.  Runs with CK_NOFORK.
 */
#include "base/hostmem.h"
#include "check_run.h"

#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

static int all_true(int local) {
    int g = 0;
    MPI_Allreduce(&local, &g, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
    return g;
}

/* The permissions ("r--s", ...) of the mapping that starts at p, or "" */
static void perms_of(const void *p, char out[8]) {
    out[0] = '\0';
    FILE *f = fopen("/proc/self/maps", "r");
    if (!f) return;
    char line[512];
    uintptr_t want = (uintptr_t)p;
    while (fgets(line, sizeof line, f)) {
        unsigned long lo = 0, hi = 0;
        char pr[8] = "";
        if (sscanf(line, "%lx-%lx %7s", &lo, &hi, pr) == 3 && lo == want) {
            snprintf(out, 8, "%s", pr);
            break;
        }
    }
    fclose(f);
}

/* Entries of /dev/shm named like a block of this program. */
static int leftovers(void) {
    DIR *d = opendir("/dev/shm");
    if (!d) return 0;
    int n = 0;
    char mine[64];
    snprintf(mine, sizeof mine, "pcdm-host-%ld-", (long)getpid());
    for (struct dirent *e; (e = readdir(d));)
        n += strncmp(e->d_name, mine, strlen(mine)) == 0;
    closedir(d);
    return n;
}

START_TEST(test_block) {
    const size_t len = 3 * 4096 + 100;
    mesh_hostmem h;
    int rc = mesh_hostmem_open(&h, MPI_COMM_WORLD, len);
    ck_assert_int_eq(all_true(rc == 0 && h.base && h.len == len), 1);
    int leaders = 0, lead = h.leader, hosts = 0;
    MPI_Comm node;
    int wr = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &wr);
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, wr, MPI_INFO_NULL, &node);
    int me = -1;
    MPI_Comm_rank(node, &me);
    MPI_Allreduce(&lead, &leaders, 1, MPI_INT, MPI_SUM, node);
    int first = me == 0;
    MPI_Allreduce(&first, &hosts, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    ck_assert_int_eq(all_true(leaders == 1 && lead == (me == 0)), 1);
    if (h.leader)
        for (size_t i = 0; i < len; i++)
            h.base[i] = (unsigned char)(i * 7 + 3);
    mesh_hostmem_seal(&h);
    int same = 1;
    for (size_t i = 0; i < len; i++)
        same &= h.base[i] == (unsigned char)(i * 7 + 3);
    char pr[8];
    perms_of(h.base, pr);
    int ro = pr[0] == 'r' && pr[1] == '-' && pr[3] == 's';
    if (!ro) fprintf(stderr, "mpi_hostmem: the sealed block is mapped '%s'\n", pr);
    int holds = mesh_hostmem_holds(&h, h.base) && mesh_hostmem_holds(&h, h.base + len - 1) &&
                !mesh_hostmem_holds(&h, h.base + len) && !mesh_hostmem_holds(&h, &h);
    ck_assert_int_eq(all_true(same), 1);
    ck_assert_int_eq(all_true(ro), 1);
    ck_assert_int_eq(all_true(holds), 1);
    ck_assert_int_eq(all_true(leftovers() == 0), 1);
    mesh_hostmem_close(&h);
    ck_assert_int_eq(all_true(h.base == NULL && !mesh_hostmem_holds(&h, pr)), 1);
    mesh_hostmem_close(&h); /* a closed block again: nothing */
    ck_assert_int_ge(hosts, 1);
    MPI_Comm_free(&node);
}
END_TEST

int main(int argc, char **argv) {
    MPI_Init(&argc, &argv);
    int rc = ck_run_mpi(ck_suite("mpi_hostmem", 0, CK_TESTS(test_block)), MPI_COMM_WORLD);
    MPI_Finalize();
    return rc;
}
