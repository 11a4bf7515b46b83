// SPDX-License-Identifier: MIT
#include "vsculpt/devices/PenSample.h"

namespace vsculpt::devices {

const char* toString(PenTool t) {
    switch (t) {
        case PenTool::None:
            return "none";
        case PenTool::Pen:
            return "pen";
        case PenTool::Eraser:
            return "eraser";
        case PenTool::Airbrush:
            return "airbrush";
        case PenTool::Mouse:
            return "mouse";
        case PenTool::Lens:
            return "lens";
    }
    return "?";
}

}  // namespace vsculpt::devices
