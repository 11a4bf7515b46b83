// SPDX-License-Identifier: MIT
#include "vsculpt/app/Cli.h"
#include "vsculpt/app/Interrupt.h"

#include <iostream>

int main(int argc, char** argv) {
    vsculpt::app::handleInterrupts();
    const int code =
        vsculpt::app::standardOutputChecked(vsculpt::app::runCli(argc, argv, std::cout, std::cerr));
    // A window closed by Ctrl-C or SIGTERM saved its work; the shell still learns why it ended.
    vsculpt::app::endIfInterrupted();
    return code;
}
