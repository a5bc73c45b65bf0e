/* cli: the one command-line front end of ./mesh, ./meshcheck, ./pcdm and ./pbw.
 *
 * Every option is one row of a table (cli_opt): its letter and/or long name, the kind and range
 * of its value (cli_value), where the value goes in cli_opts, its default and its help text.
 * The same rows parse the command line and write --help, so the two cannot disagree.  A program
 * (cli_prog) is a list of tables: the shared mesher options (-q -a -S -o --vtk --svg --stats
 * --check --progress, Triangle's switches), the parallel ones (pcdm, pbw) and its own; --help/-h
 * and --version belong to every program.  Option letters and names are unique within a program
 * (checked at every parse).  The tables and --help are cli_tables.c, the parser cli.c.
 *
 * Exit statuses, the same in every program (and on every rank of the parallel ones):
 *   0 success; 1 bad input (an unreadable or invalid file), an output error, a failed mesh or a
 *   failed check; 2 usage error (one line naming the problem, then "(try --help)").
 *
 * Syntax (the rule for every program; ./mesh --help repeats it):
 *  - "--name VALUE" or "--name=VALUE"; "--" ends the options; "-" alone is an argument.
 *  - Any other argument starting with '-' is a switch string, Triangle's syntax: its letters are
 *    options read left to right, and a letter that takes a number may have it glued on, read as
 *    far as a number goes (digits, one point, an exponent), so the next letter starts the next
 *    option: -pq30a0.01Q is -p -q 30 -a 0.01 -Q.  A row's spelling ("o2") is matched before
 *    its letters, so -o2 and -pq30o2 ask for quadratic triangles.
 *  - A letter that takes a value and has none glued on: alone in its argument (-q, -a, -S, -o),
 *    it takes the next argument (the spaced form, -q 30) -- but a letter with a bare meaning
 *    (cli_opt.bare: -q is 20 degrees, -a the regions' bounds, as in Triangle) takes it only
 *    when it looks like a number (a digit, a point or a sign first, or nan/inf: then read
 *    strictly, so "-q 30x" is an error), and otherwise stands bare: "-q lake.poly" is -q 20.
 *    Inside a longer string such a letter stands bare, or is an error if it has no bare
 *    meaning (-pS).
 *  - A string value (-o PREFIX) is glued (-oout) or spaced (-o out), and its letter must open
 *    the argument; a prefix starting with 2 is written spaced (-o 2x) since -o2 is order 2.
 *  - A Triangle letter we do not implement is refused as "not supported", any other unknown
 *    letter as "unknown option".
 * Numbers are read strictly: decimal only, no blanks, no NaN or infinities, no trailing
 * characters (a glued number ends at a letter), and integers must fit their type; the range of
 * each value is in its table row.
 *
 * Output names: without -o a mesher writes where Triangle does (cli_output_name): next to the
 * input, NAME.1.node/.ele/.poly for NAME.poly, and with -r NAME.2 for NAME.1; -N, -E, -P
 * suppress each file (-NEP: none).
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
    int pslg;                /* -p: Triangle's "the input is a PSLG" (always so here) */
} cli_opts;

typedef enum cli_kind {
    CLI_FLAG,    /* no value: the int field becomes 1 */
    CLI_HELP,    /* no value: print --help and stop (status 0) */
    CLI_VERSION, /* no value: print the name and version and stop (status 0) */
    CLI_STRING,  /* a non-empty string (const char *, pointing into argv) */
    CLI_REAL,    /* a finite double in the row's range */
    CLI_INT32,   /* an int32_t in the range */
    CLI_INT64,   /* an int64_t in the range */
    CLI_UINT64   /* any uint64_t */
} cli_kind;

/* A value's kind and checks; rows that take the same kind of value share one. */
typedef struct cli_value {
    cli_kind kind;
    const char *metavar; /* "DEG", "FILE": how --help and messages name the value */
    double min, max;     /* accepted range of a number (inclusive) */
    int min_open;        /* 1: min itself is refused ("a positive number") */
    const char *choices; /* strings: the accepted words, "a|b|c" (NULL: any non-empty string) */
    int max_open;        /* 1: max itself is refused ("below 60") */
} cli_value;

typedef struct cli_field {
    size_t offset, size; /* where the value goes in cli_opts, and its size (checked) */
} cli_field;
#define CLI_AT(f)                                                                                  \
    { offsetof(cli_opts, f), sizeof(((cli_opts *)0)->f) }

/* One option.  A table is an array of rows ended by a row whose help is NULL. */
typedef struct cli_opt {
    char letter;            /* -q: 'q'; 0: no one-letter form */
    const char *spelling;   /* flags: a longer switch-string spelling ("o2"); NULL: none */
    const char *name;       /* --vtk: "vtk"; NULL: no long form */
    const cli_value *value; /* kind, metavar and range */
    cli_field at;           /* destination (CLI_HELP: none) */
    double dflt;            /* numbers: the default, stored before parsing */
    const char *dflt_text;  /* how --help states the default; NULL: "%g" of dflt for numbers,
                               nothing for flags and strings */
    const char *bare;       /* value letters: the meaning without a value -- a number's text
                               ("20") or "--NAME", the flag row set instead; NULL: none */
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
    int triangle_names;           /* 1: without -o, par.out_prefix is Triangle's name */
} cli_prog;

/* The four programs. */
extern const cli_prog cli_mesh, cli_meshcheck, cli_pcdm, cli_pbw;

/* Local.  Parses argv[1..argc-1] for program p into *o (zeroed, then every row's default).
 * --help is written to out, usage errors and warnings to err; either may be NULL (silent, as on
 * ranks other than 0).  Returns 0 to go on, or 1 when the program must exit now with *status
 * (0 after --help, CLI_EXIT_USAGE after a usage error).  *o's strings point into argv. */
int cli_parse(const cli_prog *p, int argc, char **argv, FILE *out, FILE *err, cli_opts *o,
              int *status);

/* Local.  Triangle's output name for input (without -o): the input's name without a final
 * .poly, .node, .ele or .area, then ".1"; with refine, a final ".N" (N decimal) becomes ".N+1"
 * (lake.1 -> lake.2; without a number, or with more than 18 digits, ".1" is appended).  Returns
 * 0, or -1 if it does not fit in n bytes. */
int cli_output_name(const char *input, int refine, char *buf, size_t n);

/* Local.  Writes p's --help text (usage, options with defaults, exit statuses) to f. */
void cli_help(const cli_prog *p, FILE *f);

/* Local; a par_parse_fn for the parallel driver (run_par_main).  prog is the cli_prog (cli_pcdm or
 * cli_pbw); only rank 0 prints. */
int cli_par_parse(int argc, char **argv, int rank, const void *prog, par_opts *o, int *status);

#endif
