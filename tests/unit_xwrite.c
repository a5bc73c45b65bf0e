/* unit_xwrite: the derived outputs of io/xwrite.h on a mesh small enough to know by hand.
 *
 * The unit square split at its centre into four triangles (two regions, attributes 1.5 and -2),
 * its sides input segments with markers 5, 0, 7, 7: the edge topology (neighbours opposite each
 * corner, Triangle's edge markers: a segment's own marker, 1 on the boundary when that is 0,
 * 0 inside), and the text of .edge, .neigh, the -o2 .node/.ele, the quadratic VTK and the Gmsh
 * file with its physical groups (curves by marker, surfaces by regional attribute) and blocks.
 */
#include "check_run.h"
#include "io/meshio.h"
#include "io/xwrite.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static double sq_xy[] = {0, 0, 1, 0, 1, 1, 0, 1, 0.5, 0.5};
static int32_t sq_tri[] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
static int32_t sq_seg[] = {0, 1, 1, 2, 2, 3, 3, 0};
static int32_t sq_smk[] = {5, 0, 7, 7};
static double sq_attr[] = {1.5, 1.5, -2, -2};

static mesh_flat square(void) {
    mesh_flat m;
    memset(&m, 0, sizeof m);
    m.nverts = 5;
    m.xy = sq_xy;
    m.ntris = 4;
    m.tri = sq_tri;
    m.nsegs = 4;
    m.seg = sq_seg;
    m.smarker = sq_smk;
    m.tattr = sq_attr;
    return m;
}

START_TEST(test_topology) {
    mesh_flat m = square();
    mesh_xview x;
    mesh_xview_topo(&x, &m, NULL);
    x.nvtot = x.nsel = 5;
    x.ttot = 4;
    mesh_xview_finish(&x);
    ck_assert_int_eq(x.ne, 8);
    ck_assert_int_eq(x.nwe, 8);
    /* triangle 0 = (0, 1, 4): across (1, 4) triangle 1, across (4, 0) triangle 3, (0, 1) none */
    ck_assert_int_eq(x.nb[0], 1);
    ck_assert_int_eq(x.nb[1], 3);
    ck_assert_int_eq(x.nb[2], -1);
    ck_assert_int_eq(mesh_xview_neighbour(&x, 2), -1);
    x.tfirst = 10; /* global numbers: this part's first triangle is 10 */
    ck_assert_int_eq(mesh_xview_neighbour(&x, 0), 11);
    mesh_xview_set_remote(&x, 2, 3, 1, 77); /* rank 3: across (0, 1) rank 1's triangle 77 */
    ck_assert_int_eq(mesh_xview_neighbour(&x, 2), 77);
    ck_assert(x.eflag[x.eid[2]] & XE_OTHER);
    ck_assert(!(x.eflag[x.eid[2]] & XE_BOUND));
    /* markers: (0,1) its segment's 5; (1,2) segment marker 0 on the boundary: 1; spokes 0 */
    ck_assert_int_eq(x.emark[x.eid[2]], 5);
    ck_assert_int_eq(x.emark[x.eid[3 + 2]], 1);
    ck_assert_int_eq(x.emark[x.eid[0]], 0);
    ck_assert_int_eq(x.nwl, 4);
    /* an artificial segment is no input constraint: (1, 2) is then plain boundary */
    mesh_xview_free(&x);
    uint8_t art[4] = {1, 0, 0, 0};
    mesh_xview_topo(&x, &m, art);
    mesh_xview_finish(&x);
    ck_assert_int_eq(x.emark[x.eid[2]], 1);
    ck_assert(!(x.eflag[x.eid[2]] & XE_SEG));
    mesh_xview_free(&x);
}
END_TEST

static char *slurp(const char *path) {
    FILE *f = fopen(path, "rb");
    ck_assert_msg(f != NULL, "cannot open %s", path);
    static char buf[1 << 16];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = '\0';
    fclose(f);
    return buf;
}

#define HAS(path, text)                                                                            \
    do {                                                                                           \
        const char *s_ = slurp(path);                                                              \
        ck_assert_msg(strstr(s_, text) != NULL, "%s lacks \"%s\":\n%s", path, text, s_);           \
    } while (0)

START_TEST(test_files) {
    char dir[] = "/tmp/unit_xwrite.XXXXXX";
    ck_assert(mkdtemp(dir) != NULL);
    char prefix[128], msh[128], vtk[128], p[160], err[512];
    snprintf(prefix, sizeof prefix, "%s/sq", dir);
    snprintf(msh, sizeof msh, "%s/sq.msh", dir);
    snprintf(vtk, sizeof vtk, "%s/sq.vtk", dir);
    mesh_flat m = square();
    mesh_xreq r = {prefix, 1, 1, 1, msh, vtk, 0, NULL};
    ck_assert_msg(meshio_write_extras(&m, &r, err, sizeof err) == 0, "%s", err);
    /* edges in key order: (0,1) (0,3) (0,4) (1,2) (1,4) (2,3) (2,4) (3,4) */
    snprintf(p, sizeof p, "%s.edge", prefix);
    HAS(p, "8 1\n1 1 2 5\n2 4 1 7\n3 5 1 0\n4 2 3 1\n");
    snprintf(p, sizeof p, "%s.neigh", prefix);
    HAS(p, "4 3\n1 2 4 -1\n2 3 1 -1\n3 4 2 -1\n4 1 3 -1\n");
    /* midpoints: nodes 6.. in edge order; triangle 1's opposite corners 1, 2, 3: edges (1,4),
     * (4,0), (0,1) = nodes 10, 8, 6; its attribute 1.5 */
    snprintf(p, sizeof p, "%s.node", prefix);
    HAS(p, "13 2 0 1\n1 0 0 0\n");
    HAS(p, "\n6 0.5 0 5\n7 0 0.5 7\n8 0.25 0.25 0\n");
    snprintf(p, sizeof p, "%s.ele", prefix);
    HAS(p, "4 6 1\n1 1 2 5 10 8 6 1.5\n");
    /* VTK: 0-based, midpoints of edges 01, 12, 20 */
    HAS(vtk, "POINTS 13 double\n");
    HAS(vtk, "CELLS 4 28\n6 0 1 4 5 9 7\n");
    HAS(vtk, "CELL_TYPES 4\n22\n");
    /* Gmsh: curves by marker (1, 5, 7), surfaces by attribute (-2, 1.5) */
    HAS(msh, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    HAS(msh, "$PhysicalNames\n5\n1 1 \"marker 1\"\n1 2 \"marker 5\"\n1 3 \"marker 7\"\n"
             "2 1 \"region -2\"\n2 2 \"region 1.5\"\n$EndPhysicalNames\n");
    HAS(msh, "$Entities\n0 3 2 0\n1 0 0 0 1 1 0 1 1 0\n");
    HAS(msh, "$Nodes\n2 13 1 13\n2 1 0 5\n1\n2\n");
    HAS(msh, "$Elements\n5 8 1 8\n1 1 8 1\n");
    HAS(msh, "1 3 8 2\n");
    HAS(msh, "2 1 9 2\n7 3 4 5 11 13 12\n");
    HAS(msh, "2 2 9 2\n5 1 2 5 6 10 8\n");
    HAS(msh, "$EndElements\n");
    /* without attributes: one surface "domain"; linear elements */
    m.tattr = NULL;
    r = (mesh_xreq){NULL, 0, 0, 0, msh, NULL, 0, NULL};
    ck_assert_msg(meshio_write_extras(&m, &r, err, sizeof err) == 0, "%s", err);
    HAS(msh, "2 1 \"domain\"\n$EndPhysicalNames");
    HAS(msh, "$Nodes\n1 5 1 5\n");
    HAS(msh, "2 1 2 4\n5 1 2 5\n");
    /* an unwritable file: an error naming it */
    snprintf(p, sizeof p, "%s/no/such.msh", dir);
    r.msh = p;
    ck_assert(meshio_write_extras(&m, &r, err, sizeof err) == -1);
    ck_assert_msg(strstr(err, "no/such.msh") != NULL, "%s", err);
    if (getenv("UNIT_XWRITE_KEEP")) return;
    const char *ext[] = {".edge", ".neigh", ".node", ".ele", ".msh", ".vtk"};
    for (int k = 0; k < 6; k++) {
        snprintf(p, sizeof p, "%s%s", prefix, ext[k]);
        unlink(p);
    }
    ck_assert_msg(rmdir(dir) == 0, "%s: not empty", dir);
}
END_TEST

int main(void) {
    return ck_run(ck_suite("xwrite", 0, CK_TESTS(test_topology, test_files)));
}
