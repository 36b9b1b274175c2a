// OpenMP's wait policy for the studio (docs/lab/keep-refining.md, "The studio runs with OpenMP's
// passive wait"): the learned layer's network runs on oneDNN's OpenMP threads beside the render and
// auto's refreshes, and with libgomp's default policy its threads spin at every layer's barrier
// while their team-mates wait for a core, taking the cores from the render and from themselves.
// With OMP_WAIT_POLICY=PASSIVE they sleep there instead. libgomp reads the variable once, when it
// is loaded (before main; glibc restores the environment after the pre-initialisers, so a setenv
// there is lost), so the studio sets it and runs itself again. No Qt here: it runs before
// QApplication.
#pragma once

namespace glint::studio {

/// Whether a process whose OMP_WAIT_POLICY is `current` (null: unset) runs itself again with
/// the passive wait: only when it is unset (a user's value, even an empty one, is kept).
bool runAgainForPassiveWait(const char* current);

/// First thing in main: when OMP_WAIT_POLICY is unset, sets it to PASSIVE (with a marker,
/// GLINT_STUDIO_SET_OMP_WAIT_POLICY) and replaces the process by `program` (this executable by
/// default) with the same `argv`. Returns only when it did not: in the process run again it
/// unsets both (libgomp has read the variable; the processes the studio starts get the user's
/// environment), a user's value is kept, or the exec failed (then both are unset again and the
/// process goes on with libgomp's default).
void usePassiveOpenMpWait(char** argv, const char* program = "/proc/self/exe");

}  // namespace glint::studio
