/* mesh_subseg.c: the subsegment side table (mesh.h, mesh_subseg).
 *
 * Every piece of an input segment that is an edge of the mesh has a record: its endpoints, its
 * segment and, for a dyadic piece, its name (level j, index k: the piece from k/2^j to
 * (k+1)/2^j of the segment, whose split point mesh_dyadic_point computes from the segment's
 * endpoints alone, so two meshes that split the same piece make the same point bit for bit --
 * what PCDM's interface splits rely on).  Records are found by endpoint pair and by name through
 * two open-addressing hash tables (linear probing, backward-shift deletion, no tombstones),
 * rebuilt at twice the size when half full; freed records form a free list.  Invariants: each
 * live record is in the pair table once and, when named, in the name table once; seg_nsub
 * counts the live records of each segment.
 */
#include "mesh_impl.h"

#include <math.h>

/* ---- subsegment side table ---------------------------------------------------------------- */

static uint64_t hash_pair(int32_t u, int32_t v) {
    uint32_t a = (uint32_t)(u < v ? u : v), b = (uint32_t)(u < v ? v : u);
    return mesh_hash64(((uint64_t)a << 32) | b);
}

static uint64_t hash_name(int32_t seg, int32_t level, int64_t k) {
    return mesh_hash64((uint64_t)k * 0x9e3779b97f4a7c15ull ^
                       mesh_hash64(((uint64_t)(uint32_t)seg << 8) | (uint64_t)(uint8_t)level));
}

static uint64_t rec_hash(const mesh *m, int which, int32_t r) {
    const mesh_subseg *s = &m->ss[r];
    return which == 0 ? hash_pair(s->u, s->v) : hash_name(s->seg, s->level, s->k);
}

static void tab_put(mesh *m, int32_t *tab, int which, int32_t r) {
    uint32_t mask = m->hcap - 1, i = (uint32_t)rec_hash(m, which, r) & mask;
    while (tab[i] >= 0)
        i = (i + 1) & mask;
    tab[i] = r;
}

static void tab_del(mesh *m, int32_t *tab, int which, int32_t r) {
    uint32_t mask = m->hcap - 1, i = (uint32_t)rec_hash(m, which, r) & mask;
    while (tab[i] != r) {
        if (tab[i] < 0) MESH_BUG("subsegment record %d missing from its table", r);
        i = (i + 1) & mask;
    }
    /* backward-shift deletion (linear probing, no tombstones) */
    uint32_t j = i;
    for (;;) {
        j = (j + 1) & mask;
        if (tab[j] < 0) break;
        uint32_t h = (uint32_t)rec_hash(m, which, tab[j]) & mask;
        int stays = (i <= j) ? (i < h && h <= j) : (i < h || h <= j);
        if (stays) continue;
        tab[i] = tab[j];
        i = j;
    }
    tab[i] = -1;
}

static void tab_rebuild(mesh *m, uint32_t cap) {
    free(m->hpair);
    free(m->hname);
    m->hcap = cap;
    m->hpair = mesh_xrealloc(NULL, cap, sizeof(int32_t));
    m->hname = mesh_xrealloc(NULL, cap, sizeof(int32_t));
    for (uint32_t i = 0; i < cap; i++)
        m->hpair[i] = m->hname[i] = -1;
    for (int32_t r = 0; r < m->nss; r++) {
        if (m->ss[r].level == -2) continue;
        tab_put(m, m->hpair, 0, r);
        if (m->ss[r].level >= 0) tab_put(m, m->hname, 1, r);
    }
}

void mesh_ss_reserve(mesh *m, int32_t n) {
    if (n <= 0) return;
    int64_t cap = m->sscap ? m->sscap : 64;
    while (cap < n)
        cap *= 2;
    if (cap > m->sscap) {
        m->sscap = (int32_t)cap;
        m->ss = mesh_xrealloc(m->ss, m->sscap, sizeof(mesh_subseg));
    }
    uint64_t h = m->hcap ? m->hcap : 256; /* as mesh_ss_add's growth: 2 live < hcap */
    while (2 * (uint64_t)n >= h)
        h *= 2;
    if (h > m->hcap) tab_rebuild(m, (uint32_t)h);
}

int32_t mesh_ss_add(mesh *m, int32_t u, int32_t v, int32_t seg, int32_t level, int64_t k) {
    int32_t r;
    if (m->ss_free >= 0) {
        r = m->ss_free;
        m->ss_free = m->ss[r].u;
    } else {
        if (m->nss == m->sscap) {
            m->sscap = m->sscap ? m->sscap * 2 : 64;
            m->ss = mesh_xrealloc(m->ss, m->sscap, sizeof(mesh_subseg));
        }
        r = m->nss++;
    }
    mesh_subseg *s = &m->ss[r];
    s->u = u, s->v = v, s->seg = seg, s->level = level, s->k = k;
    m->ss_live++;
    m->seg_nsub[seg]++;
    if ((uint32_t)m->ss_live * 2 >= m->hcap) {
        tab_rebuild(m, m->hcap ? m->hcap * 2 : 256);
    } else {
        tab_put(m, m->hpair, 0, r);
        if (level >= 0) tab_put(m, m->hname, 1, r);
    }
    return r;
}

void mesh_ss_del(mesh *m, int32_t r) {
    mesh_subseg *s = &m->ss[r];
    tab_del(m, m->hpair, 0, r);
    if (s->level >= 0) tab_del(m, m->hname, 1, r);
    m->seg_nsub[s->seg]--;
    s->level = -2;
    s->u = m->ss_free;
    m->ss_free = r;
    m->ss_live--;
}

void mesh_ss_prefetch(const mesh *m, int32_t u, int32_t v, int32_t seg, int32_t level, int64_t k) {
    if (m->hcap == 0) return;
    uint32_t mask = m->hcap - 1;
    __builtin_prefetch(&m->hpair[(uint32_t)hash_pair(u, v) & mask], 1);
    if (level >= 0) __builtin_prefetch(&m->hname[(uint32_t)hash_name(seg, level, k) & mask], 1);
}

int32_t mesh_ss_find_pair(const mesh *m, int32_t u, int32_t v) {
    if (m->hcap == 0) return -1;
    uint32_t mask = m->hcap - 1, i = (uint32_t)hash_pair(u, v) & mask;
    for (;; i = (i + 1) & mask) {
        int32_t r = m->hpair[i];
        if (r < 0) return -1;
        const mesh_subseg *s = &m->ss[r];
        if ((s->u == u && s->v == v) || (s->u == v && s->v == u)) return r;
    }
}

int32_t mesh_ss_find_name(const mesh *m, int32_t seg, int32_t level, int64_t k) {
    if (m->hcap == 0 || level < 0) return -1;
    uint32_t mask = m->hcap - 1, i = (uint32_t)hash_name(seg, level, k) & mask;
    for (;; i = (i + 1) & mask) {
        int32_t r = m->hname[i];
        if (r < 0) return -1;
        const mesh_subseg *s = &m->ss[r];
        if (s->seg == seg && s->level == level && s->k == k) return r;
    }
}

void mesh_ss_prune(mesh *m) {
    for (int32_t r = 0; r < m->nss; r++) {
        if (m->ss[r].level == -2) continue;
        if (mesh_find_edge(m, m->ss[r].u, m->ss[r].v) < 0) mesh_ss_del(m, r);
    }
}

const mesh_subseg *mesh_subseg_of_edge(const mesh *m, int32_t e) {
    if (!mesh_edge_constrained(m, e)) return NULL;
    int32_t r = mesh_ss_find_pair(m, mesh_org(m, e), mesh_dest(m, e));
    return r < 0 ? NULL : &m->ss[r];
}

void mesh_dyadic_point(const double a[2], const double b[2], int32_t level, int64_t k,
                       double out[2]) {
    double f = ldexp((double)(2 * k + 1), -(level + 1));
    out[0] = a[0] + (b[0] - a[0]) * f;
    out[1] = a[1] + (b[1] - a[1]) * f;
}
