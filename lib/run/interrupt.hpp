#pragma once
// Ctrl-C and SIGTERM ask the run to stop at the end of the current step, write a checkpoint and a
// partial report, and exit with status 130: nothing is lost on interrupt.
namespace mrjam {

void install_interrupt_handler();
bool interrupt_requested();
void request_interrupt();  // for tests
void clear_interrupt();    // for tests: the flag is process-wide

}  // namespace mrjam
