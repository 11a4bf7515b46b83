// SPDX-License-Identifier: MIT
#include "vsculpt/app/Cli.h"

#include <iostream>

int main(int argc, char** argv) {
    vsculpt::app::removeTemporaryFilesOnInterrupt();
    return vsculpt::app::runCli(argc, argv, std::cout, std::cerr);
}
