// SPDX-License-Identifier: MIT
#include "vsculpt/devices/DecodeStatus.h"

namespace vsculpt::devices {

const char* toString(DecodeStatus s) {
    switch (s) {
        case DecodeStatus::Ok:
            return "ok";
        case DecodeStatus::Empty:
            return "empty report";
        case DecodeStatus::Truncated:
            return "truncated report";
        case DecodeStatus::UnknownReport:
            return "unknown report id";
        case DecodeStatus::Malformed:
            return "malformed report";
    }
    return "?";
}

}  // namespace vsculpt::devices
