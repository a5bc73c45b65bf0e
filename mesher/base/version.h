/* version: the one place the project's version is stated.  ./mesh, ./meshcheck, ./pcdm and
 * ./pbw print it for --version (apps/cli.c); anything else that needs it (a library's
 * pkg-config file, a release name) takes it from here, e.g.
 *   sed -n 's/^#define PCDM_VERSION "\(.*\)"$/\1/p' mesher/base/version.h
 * Semantic versioning: MAJOR.MINOR.PATCH.
 */
#ifndef MESH_VERSION_H
#define MESH_VERSION_H

#define PCDM_VERSION "0.15.0"

#endif
