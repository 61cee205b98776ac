/* foldsim's C library: docs/interop.md. Link with -lfoldsim_c (libfoldsim_c.so or .a). */

#ifndef FOLDSIM_H
#define FOLDSIM_H

/* Written by cbindgen from capi/src/lib.rs: do not edit (FOLDSIM_WRITE_HEADER=1 cargo test -p foldsim-c --test header). */

#include <stddef.h>

// What a call returns.
typedef enum FoldsimStatus {
  // Done.
  FOLDSIM_OK = 0,
  // A pointer argument was null.
  FOLDSIM_ERROR_NULL = 1,
  // An argument was wrong: an unknown name, a value that is not finite, an index out of
  // range, text that is not UTF-8.
  FOLDSIM_ERROR_ARGUMENT = 2,
  // The call is not allowed now (a parameter after the start, an advance before it).
  FOLDSIM_ERROR_STATE = 3,
  // The scenario is not valid, or the run failed (its message says why).
  FOLDSIM_ERROR_RUN = 4,
  // A bug in foldsim (please report it with the message).
  FOLDSIM_ERROR_INTERNAL = 5,
} FoldsimStatus;

// A scenario loaded, and once started, its run (opaque to C).
typedef struct FoldsimSimulation FoldsimSimulation;

#ifdef __cplusplus
extern "C" {
#endif // __cplusplus

// Loads the scenario file `path` (TOML, docs/scenario.md; its table files relative to it)
// and checks it. Returns the simulation, or null with the reason in [`foldsim_last_error`].
//
// # Safety
// `path` is null or a NUL-terminated string.
struct FoldsimSimulation *foldsim_load_file(const char *path);

// Loads a scenario from its TOML text; `base_dir` (may be null: the current directory) is
// where its table files are read from. Returns the simulation, or null with the reason in
// [`foldsim_last_error`].
//
// # Safety
// `toml` and `base_dir` are null or NUL-terminated strings.
struct FoldsimSimulation *foldsim_load_text(const char *toml, const char *base_dir);

// Sets the scenario's number at `key_path` (docs/scenario.md, "Key paths"; `*` sets every
// list entry it matches) to `value`, before [`foldsim_start`]. The parameters are the
// numbers the file writes as single values outside `[run]`; the changed scenario is checked
// at once (a negative mass is refused here, and the change undone).
//
// # Safety
// `sim` is a live handle; `key_path` is null or NUL-terminated.
enum FoldsimStatus foldsim_set_parameter(struct FoldsimSimulation *sim,
                                         const char *key_path,
                                         double value);

// Starts the run at t = 0: the scenario built with its parameters, the inputs set so far
// applied. Fails if already started, or as a run's start fails.
//
// # Safety
// `sim` is a live handle.
enum FoldsimStatus foldsim_start(struct FoldsimSimulation *sim);

// The number of inputs (every body's six, every motor's, every actuator's); 0 for null.
//
// # Safety
// `sim` is null or a live handle.
size_t foldsim_input_count(const struct FoldsimSimulation *sim);

// Input `index`'s name (`hub_T_z`), or null out of range; valid while the simulation lives.
//
// # Safety
// `sim` is null or a live handle.
const char *foldsim_input_name(const struct FoldsimSimulation *sim, size_t index);

// The number of outputs (the CSV columns, docs/outputs.md); 0 for null.
//
// # Safety
// `sim` is null or a live handle.
size_t foldsim_output_count(const struct FoldsimSimulation *sim);

// Output `index`'s name (`H_z`), or null out of range; valid while the simulation lives.
//
// # Safety
// `sim` is null or a live handle.
const char *foldsim_output_name(const struct FoldsimSimulation *sim, size_t index);

// Sets the input `name` (its unit: N, N·m; forces and torques in the body's own frame) to
// `value` from now on, held until set again. Before the start it is applied at the start.
//
// # Safety
// `sim` is a live handle; `name` is null or NUL-terminated.
enum FoldsimStatus foldsim_set_input(struct FoldsimSimulation *sim, const char *name, double value);

// As [`foldsim_set_input`], by the input's index (faster in a loop).
//
// # Safety
// `sim` is a live handle.
enum FoldsimStatus foldsim_set_input_at(struct FoldsimSimulation *sim, size_t index, double value);

// Integrates to exactly t + `dt` (s) with the scenario's integrator, the inputs held.
// Fails for `dt` ≤ 0 or not finite, past `run.duration` (the run's horizon), before the
// start, or as a run fails (the message says why; the state stays where it stopped).
//
// # Safety
// `sim` is a live handle.
enum FoldsimStatus foldsim_advance(struct FoldsimSimulation *sim, double dt);

// Writes the time reached (s) to `*t`.
//
// # Safety
// `sim` is a live handle; `t` is null or points at a double.
enum FoldsimStatus foldsim_time(struct FoldsimSimulation *sim, double *t);

// Writes the output `name` at the time reached to `*value`.
//
// # Safety
// `sim` is a live handle; `name` is null or NUL-terminated; `value` is null or points at a
// double.
enum FoldsimStatus foldsim_get_output(struct FoldsimSimulation *sim,
                                      const char *name,
                                      double *value);

// Writes every output at the time reached to `values` (`count` must be
// [`foldsim_output_count`]), in [`foldsim_output_name`]'s order.
//
// # Safety
// `sim` is a live handle; `values` is null or points at `count` doubles.
enum FoldsimStatus foldsim_get_outputs(struct FoldsimSimulation *sim, double *values, size_t count);

// The last error's message on this thread (empty if none); valid until the next failing
// call on this thread.
const char *foldsim_last_error(void);

// Frees a simulation (null is ignored).
//
// # Safety
// `sim` is null or a handle not yet freed; it is not used again.
void foldsim_free(struct FoldsimSimulation *sim);

// foldsim's version ("0.1.0").
const char *foldsim_version(void);

#ifdef __cplusplus
}  // extern "C"
#endif  // __cplusplus

#endif  /* FOLDSIM_H */
