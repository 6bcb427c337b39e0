// quiet_occt_messages(): OCCT keeps its messages on one global messenger,
// whose default printer writes to stdout. STEP readers and the STEP writer
// print their statistics there, which would corrupt the `--json` output of
// the command line and clutter the user's terminal. Called before any OCCT
// data exchange; idempotent and thread-safe.
#pragma once

namespace stripweave {

void quiet_occt_messages();

}  // namespace stripweave
