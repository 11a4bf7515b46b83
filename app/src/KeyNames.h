// SPDX-License-Identifier: MIT
// Key names as configs spell them ("TAB", "Z", "F5", ...), for both windows. Internal to app/.
#pragma once

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>  // key codes only

#include "vsculpt/core/Config.h"
#include "vsculpt/core/PrintableText.h"

#include <cstdlib>
#include <map>
#include <string>

#include <spdlog/spdlog.h>

namespace vsculpt::app {

/// GLFW key code for a key name from configs ("TAB", "Z", "7", "F5", ...), or -1.
inline int keyCode(const std::string& name) {
    if (name.size() == 1 && name[0] >= 'A' && name[0] <= 'Z') return GLFW_KEY_A + (name[0] - 'A');
    if (name.size() == 1 && name[0] >= '0' && name[0] <= '9') return GLFW_KEY_0 + (name[0] - '0');
    if (name.size() >= 2 && name[0] == 'F') {
        const int n = std::atoi(name.c_str() + 1);
        if (n >= 1 && n <= 12 && name == "F" + std::to_string(n)) return GLFW_KEY_F1 + n - 1;
    }
    static const std::map<std::string, int> named = {{"TAB", GLFW_KEY_TAB},
                                                     {"SPACE", GLFW_KEY_SPACE},
                                                     {"ESCAPE", GLFW_KEY_ESCAPE},
                                                     {"ENTER", GLFW_KEY_ENTER},
                                                     {"BACKSPACE", GLFW_KEY_BACKSPACE},
                                                     {"DELETE", GLFW_KEY_DELETE},
                                                     {"LEFT", GLFW_KEY_LEFT},
                                                     {"RIGHT", GLFW_KEY_RIGHT},
                                                     {"UP", GLFW_KEY_UP},
                                                     {"DOWN", GLFW_KEY_DOWN},
                                                     {"PAGE_UP", GLFW_KEY_PAGE_UP},
                                                     {"PAGE_DOWN", GLFW_KEY_PAGE_DOWN},
                                                     {"HOME", GLFW_KEY_HOME},
                                                     {"END", GLFW_KEY_END},
                                                     {"MINUS", GLFW_KEY_MINUS},
                                                     {"EQUAL", GLFW_KEY_EQUAL},
                                                     {"COMMA", GLFW_KEY_COMMA},
                                                     {"PERIOD", GLFW_KEY_PERIOD}};
    auto it = named.find(name);
    return it == named.end() ? -1 : it->second;
}

/// A binding table (interaction.bindings or interaction.sketch_bindings) by key code. False
/// (and an error logged, naming the config file and the binding) for an unknown key name or a
/// key bound twice.
inline bool bindingsByKey(const core::SculptConfig& cfg,
                          const std::map<std::string, std::string>& bindings,
                          const std::string& section, std::map<int, std::string>& actionOfKey) {
    for (const auto& [action, key] : bindings) {
        const int code = keyCode(key);
        if (code < 0) {
            spdlog::error(
                "{}: interaction.{}.{}: unknown key name '{}' (use A-Z, 0-9, F1-F12, "
                "TAB, SPACE, ...)",
                cfg.source, section, action, core::printableText(key));
            return false;
        }
        if (actionOfKey.count(code)) {
            spdlog::error("{}: interaction.{}.{}: key '{}' is already bound to {}", cfg.source,
                          section, action, core::printableText(key), actionOfKey[code]);
            return false;
        }
        actionOfKey[code] = action;
    }
    return true;
}

}  // namespace vsculpt::app
