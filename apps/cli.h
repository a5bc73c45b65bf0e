/* cli: the one command-line front end of ./mesh, ./meshcheck, ./pcdm and ./pbw.
 *
 * Every option is one row of a table (cli_opt): its letter and/or long name, the kind and range
 * of its value (cli_value), where the value goes in cli_opts, its default and its help text.
 * The same rows parse the command line and write --help, so the two cannot disagree.  A program
 * (cli_prog) is a list of tables: the shared mesher options (-q -a -S -o --vtk --svg --stats
 * --check --progress), the parallel ones (pcdm, pbw) and its own; --help/-h belongs to every
 * program.  Option letters and names are unique within a program (checked at every parse).
 *
 * Exit statuses, the same in every program (and on every rank of the parallel ones):
 *   0 success; 1 bad input (an unreadable or invalid file), an output error, a failed mesh or a
 *   failed check; 2 usage error (one line naming the problem, then "(try --help)").
 *
 * Syntax: -q 30 or -q30; --vtk FILE or --vtk=FILE; "--" ends the options.  Numbers are read
 * strictly: decimal only, no blanks, no NaN or infinities, no trailing characters, and integers
 * must fit their type; the range of each value is in its table row.
 *
 * Extension point: a Triangle-style switch string (-pq30a0.01Q) is a walk over one argument's
 * letters, each looked up by cli_opt.letter, whose value is the number glued after it.  The
 * value readers already report where a number ends, so that syntax needs a third branch in the
 * argument loop (cli.c), not another parser.
 *
 * All functions are Local and keep no state between calls; the tables are constant.
 */
#ifndef CLI_H
#define CLI_H

#include <stddef.h>
#include <stdio.h>

#include "par/par.h"

enum { CLI_EXIT_OK = 0, CLI_EXIT_FAIL = 1, CLI_EXIT_USAGE = 2 };

/* Everything any program can be told.  The shared options and the parallel ones live in par
 * (mesher/par/par.h: what ./pcdm and ./pbw hand to their layers); par.prog is the program's
 * name and par.input its first argument. */
typedef struct cli_opts {
    par_opts par;
    int lens;                /* ./mesh --lens: diametral lenses decide encroachment */
    int cdt_only;            /* ./mesh --cdt-only: no refinement */
    int interfaces_delaunay; /* ./meshcheck --interfaces-delaunay */
    const char *mesh_prefix; /* ./meshcheck: its second argument */
} cli_opts;

typedef enum cli_kind {
    CLI_FLAG,   /* no value: the int field becomes 1 */
    CLI_HELP,   /* no value: print --help and stop (status 0) */
    CLI_STRING, /* a non-empty string (const char *, pointing into argv) */
    CLI_REAL,   /* a finite double in the row's range */
    CLI_INT32,  /* an int32_t in the range */
    CLI_INT64,  /* an int64_t in the range */
    CLI_UINT64  /* any uint64_t */
} cli_kind;

/* A value's kind and checks; rows that take the same kind of value share one. */
typedef struct cli_value {
    cli_kind kind;
    const char *metavar; /* "DEG", "FILE": how --help and messages name the value */
    double min, max;     /* accepted range of a number (inclusive) */
    int min_open;        /* 1: min itself is refused ("a positive number") */
} cli_value;

typedef struct cli_field {
    size_t offset, size; /* where the value goes in cli_opts, and its size (checked) */
} cli_field;
#define CLI_AT(f)                                                                                  \
    { offsetof(cli_opts, f), sizeof(((cli_opts *)0)->f) }

/* One option.  A table is an array of rows ended by a row whose help is NULL. */
typedef struct cli_opt {
    char letter;            /* -q: 'q'; 0: no one-letter form */
    const char *name;       /* --vtk: "vtk"; NULL: no long form */
    const cli_value *value; /* kind, metavar and range */
    cli_field at;           /* destination (CLI_HELP: none) */
    double dflt;            /* numbers: the default, stored before parsing */
    const char *dflt_text;  /* how --help states the default; NULL: "%g" of dflt for numbers,
                               nothing for flags and strings */
    double warn_above;      /* numbers: a value above it is accepted with a warning (0: never) */
    const char *warning;    /* ... saying this */
    const char *help;       /* one sentence, no trailing period */
} cli_opt;

typedef struct cli_prog {
    const char *name;             /* "mesh": message prefix and par.prog */
    const char *usage;            /* "./mesh [options] input.poly" */
    const char *about;            /* one line under the usage line */
    const cli_opt *const *tables; /* NULL-terminated */
    const char *args[2];          /* required positional arguments (NULL: fewer) */
    const char *notes;            /* printed at the end of --help; may be NULL */
} cli_prog;

/* The four programs. */
extern const cli_prog cli_mesh, cli_meshcheck, cli_pcdm, cli_pbw;

/* Local.  Parses argv[1..argc-1] for program p into *o (zeroed, then every row's default).
 * --help is written to out, usage errors and warnings to err; either may be NULL (silent, as on
 * ranks other than 0).  Returns 0 to go on, or 1 when the program must exit now with *status
 * (0 after --help, CLI_EXIT_USAGE after a usage error).  *o's strings point into argv. */
int cli_parse(const cli_prog *p, int argc, char **argv, FILE *out, FILE *err, cli_opts *o,
              int *status);

/* Local.  Writes p's --help text (usage, options with defaults, exit statuses) to f. */
void cli_help(const cli_prog *p, FILE *f);

/* Local; a par_parse_fn for par_startup.  prog is the cli_prog (cli_pcdm or cli_pbw); only
 * rank 0 prints. */
int cli_par_parse(int argc, char **argv, int rank, const void *prog, par_opts *o, int *status);

#endif
