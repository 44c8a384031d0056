#pragma once
// Ctrl-C (SIGINT) and kill (SIGTERM) during a long run: the handler removes the temporary files of
// atomic writes in flight (util/atomic_file.h), prints one line saying what is kept and how to go
// on, and exits with 128 + the signal number. Nothing else needs to be undone: outputs appear only
// by rename once complete, journals are append-only and their cut tail is dropped on --resume.
// A full disk under RLIMIT_FSIZE must be a write error, not a kill: SIGXFSZ is ignored.
namespace cdbench {

// `hint` (a string literal: the handler may only read it) ends the message.
void install_interrupt_handlers(const char* hint);

// The run's outputs are all in place: from now on SIGINT and SIGTERM are ignored, and the process
// finishes normally instead of reporting an interruption that cost nothing (called by a command
// once its last output is written, before printing its summary and exiting).
void mark_outputs_complete();

// The handler's list of temporary files (a fixed number of slots; -1 when all are taken, in
// which case the file is only removed by its writer).
int register_temporary_file(const char* path);
void unregister_temporary_file(int slot);

}  // namespace cdbench
