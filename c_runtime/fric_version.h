/* fricgen C runtime: its version, as numbers #if can test.
 * Part of fricgen; copied by `fricgen emit` beside every float model. Every generated NAME.h that
 * uses the runtime records the version it was emitted against (NAME_FRICGEN_VERSION_MAJOR, ...)
 * and stops the build with #error when this runtime's major or minor version differs: re-emit
 * the model (or every model of the folder) with one fricgen, so that models and runtime match.
 * `fricgen emit` writes these numbers from fricgen's version (fricgen.codegen.context).
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the fricgen authors */
#ifndef FRIC_VERSION_H
#define FRIC_VERSION_H

#define FRIC_RUNTIME_VERSION_MAJOR 0
#define FRIC_RUNTIME_VERSION_MINOR 1
#define FRIC_RUNTIME_VERSION_PATCH 0

#endif /* FRIC_VERSION_H */
