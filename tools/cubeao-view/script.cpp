#include "cubeao-view/script.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "cubeao/core/error.h"

namespace cubeao::viewer {
namespace {

// The argument shape of each verb: N = that many numbers, T = one word (file, mode, on/off).
struct Grammar {
    const char* verb;
    int numbers;
    bool text;
    const char* usage;
};

constexpr Grammar kGrammar[] = {
    {"frames", 1, false, "frames N"},
    {"path", 1, false, "path F"},
    {"play", 2, false, "play A B"},
    {"eye", 3, false, "eye X Y Z"},
    {"look", 3, false, "look X Y Z"},
    {"move", 3, false, "move RIGHT UP FORWARD"},
    {"turn", 2, false, "turn YAW_DEG PITCH_DEG"},
    {"walk", 4, false, "walk RIGHT UP FORWARD FRAMES"},
    {"size", 2, false, "size WIDTH HEIGHT"},
    {"mode", 0, true, "mode NAME"},
    {"baseline", 0, true, "baseline gtao|hbao|alchemy"},
    {"live", 0, true, "live on|off"},
    {"idle", 1, false, "idle N"},
    {"settle", 1, false, "settle MAX_FRAMES"},
    {"rebake", 1, false, "rebake MAX_FRAMES"},
    {"screenshot", 0, true, "screenshot FILE.png|FILE.exr"},
    {"screenshot-window", 0, true, "screenshot-window FILE.png"},
    {"save", 0, true, "save FILE.cubeao"},
    {"record", 0, true, "record FILE.json | record stop"},
    {"quit", 0, false, "quit"},
};

// Counts: frames, play's ends and sizes are whole and not negative; a counting verb takes at most
// a day of frames at 60 Hz, so a typo cannot hang a test for hours.
void checkNumbers(const ScriptCommand& c, const std::string& where) {
    const auto whole = [&](double v, double lo, double hi, const char* what) {
        if (!(v >= lo && v <= hi && std::floor(v) == v))
            throw UsageError(where + ": " + what + " must be a whole number in [" + std::to_string(int(lo)) + ", " +
                             std::to_string(int(hi)) + "], got " + std::to_string(v));
    };
    constexpr double kMaxFrames = 24.0 * 3600.0 * 60.0;
    if (c.verb == "frames" || c.verb == "idle" || c.verb == "settle" || c.verb == "rebake") whole(c.numbers[0], 0, kMaxFrames, "the frame count");
    if (c.verb == "path") whole(c.numbers[0], 0, kMaxFrames, "the path frame");
    if (c.verb == "play") {
        whole(c.numbers[0], 0, kMaxFrames, "the first frame");
        whole(c.numbers[1], c.numbers[0], kMaxFrames, "the end frame (after the first)");
    }
    if (c.verb == "walk") whole(c.numbers[3], 1, kMaxFrames, "the frame count");
    if (c.verb == "size") {
        whole(c.numbers[0], 8, 8192, "the width");
        whole(c.numbers[1], 8, 8192, "the height");
    }
    for (double v : c.numbers)
        if (!std::isfinite(v)) throw UsageError(where + ": numbers must be finite");
}

}  // namespace

std::vector<ScriptCommand> parseScript(const std::string& text, const std::string& source) {
    std::vector<ScriptCommand> commands;
    std::istringstream lines(text);
    std::string line;
    for (int number = 1; std::getline(lines, line); ++number) {
        if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
        std::istringstream words(line);
        std::vector<std::string> w;
        for (std::string word; words >> word;) w.push_back(word);
        if (w.empty()) continue;
        const std::string where = source + ":" + std::to_string(number);
        ScriptCommand c;
        c.line = number;
        c.verb = w[0];
        for (char& ch : c.verb) ch = char(std::tolower(static_cast<unsigned char>(ch)));
        const Grammar* g = nullptr;
        for (const Grammar& candidate : kGrammar)
            if (c.verb == candidate.verb) g = &candidate;
        if (!g) {
            std::string verbs;
            for (const Grammar& candidate : kGrammar) verbs += std::string(verbs.empty() ? "" : ", ") + candidate.verb;
            throw UsageError(where + ": unknown command \"" + w[0] + "\"; expected one of " + verbs);
        }
        const std::size_t expected = std::size_t(g->numbers) + (g->text ? 1 : 0);
        if (w.size() - 1 != expected) throw UsageError(where + ": expected \"" + g->usage + "\"");
        for (int i = 0; i < g->numbers; ++i) {
            const std::string& s = w[std::size_t(i) + 1];
            double v = 0.0;
            const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
            if (ec != std::errc() || end != s.data() + s.size())
                throw UsageError(where + ": \"" + s + "\" is not a number (expected \"" + g->usage + "\")");
            c.numbers.push_back(v);
        }
        if (g->text) c.text = w.back();
        if ((c.verb == "live") && c.text != "on" && c.text != "off")
            throw UsageError(where + ": expected \"live on\" or \"live off\"");
        checkNumbers(c, where);
        commands.push_back(std::move(c));
    }
    return commands;
}

std::vector<ScriptCommand> readScript(const std::filesystem::path& file) {
    std::ifstream in(file);
    if (!in) throw UsageError("--script " + file.string() + ": cannot open the file");
    std::stringstream text;
    text << in.rdbuf();
    return parseScript(text.str(), file.string());
}

}  // namespace cubeao::viewer
