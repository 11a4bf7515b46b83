// SPDX-License-Identifier: MIT
/// @file DecodeStatus.h
/// @brief Why a pure decoder refused a report. Every driver's decoder reports one of these so
/// the transport can count drops per device and reason.
#pragma once

namespace vsculpt::devices {

enum class DecodeStatus {
    Ok,
    Empty,          ///< zero bytes
    Truncated,      ///< shorter than its layout
    UnknownReport,  ///< a report id / record type this decoder does not know
    Malformed,      ///< right length, impossible content (bad sync byte, checksum, range)
};

const char* toString(DecodeStatus s);

}  // namespace vsculpt::devices
