#include "cubeao-view/script.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>

#include "cubeao-view/view_mode.h"
#include "cubeao/core/error.h"

namespace cubeao::viewer {
namespace {

// The argument shape of each verb: N = that many numbers, T = one word (file, mode, on/off).
struct Grammar {
    Verb verb;
    const char* name;
    int numbers;
    bool text;
    const char* usage;
};

constexpr Grammar kGrammar[] = {
    {Verb::Frames, "frames", 1, false, "frames N"},
    {Verb::Path, "path", 1, false, "path F"},
    {Verb::Play, "play", 2, false, "play A B"},
    {Verb::Eye, "eye", 3, false, "eye X Y Z"},
    {Verb::Look, "look", 3, false, "look X Y Z"},
    {Verb::Move, "move", 3, false, "move RIGHT UP FORWARD"},
    {Verb::Turn, "turn", 2, false, "turn YAW_DEG PITCH_DEG"},
    {Verb::Walk, "walk", 4, false, "walk RIGHT UP FORWARD FRAMES"},
    {Verb::Size, "size", 2, false, "size WIDTH HEIGHT"},
    {Verb::Mode, "mode", 0, true, "mode NAME"},
    {Verb::Baseline, "baseline", 0, true, "baseline gtao|hbao|alchemy"},
    {Verb::Live, "live", 0, true, "live on|off"},
    {Verb::Idle, "idle", 1, false, "idle N"},
    {Verb::Settle, "settle", 1, false, "settle MAX_FRAMES"},
    {Verb::Rebake, "rebake", 1, false, "rebake MAX_FRAMES"},
    {Verb::Screenshot, "screenshot", 0, true, "screenshot FILE.png|FILE.exr"},
    {Verb::ScreenshotWindow, "screenshot-window", 0, true, "screenshot-window FILE.png"},
    {Verb::Save, "save", 0, true, "save FILE.cubeao"},
    {Verb::Record, "record", 0, true, "record FILE.json | record stop"},
    {Verb::Quit, "quit", 0, false, "quit"},
};

// One row per verb in the enum's order, so verbName can index it.
constexpr bool grammarInEnumOrder() {
    for (std::size_t i = 0; i < std::size(kGrammar); ++i)
        if (std::size_t(kGrammar[i].verb) != i) return false;
    return std::size(kGrammar) == std::size_t(Verb::Quit) + 1;
}
static_assert(grammarInEnumOrder());

// Counts: frames, play's ends and sizes are whole and not negative; a counting verb takes at most
// a day of frames at 60 Hz, so a typo cannot hang a test for hours.
void checkNumbers(const ScriptCommand& c, const std::string& where) {
    const auto whole = [&](double v, double lo, double hi, const char* what) {
        if (!(v >= lo && v <= hi && std::floor(v) == v))
            throw UsageError(where + ": " + what + " must be a whole number in [" + std::to_string(int(lo)) + ", " +
                             std::to_string(int(hi)) + "], got " + std::to_string(v));
    };
    constexpr double kMaxFrames = 24.0 * 3600.0 * 60.0;
    switch (c.verb) {
        case Verb::Frames:
        case Verb::Idle:
        case Verb::Settle:
        case Verb::Rebake: whole(c.numbers[0], 0, kMaxFrames, "the frame count"); break;
        case Verb::Path: whole(c.numbers[0], 0, kMaxFrames, "the path frame"); break;
        case Verb::Play:
            whole(c.numbers[0], 0, kMaxFrames, "the first frame");
            whole(c.numbers[1], c.numbers[0], kMaxFrames, "the end frame (after the first)");
            break;
        case Verb::Walk: whole(c.numbers[3], 1, kMaxFrames, "the frame count"); break;
        case Verb::Size:
            whole(c.numbers[0], 8, 8192, "the width");
            whole(c.numbers[1], 8, 8192, "the height");
            break;
        default: break;
    }
    for (double v : c.numbers)
        if (!std::isfinite(v)) throw UsageError(where + ": numbers must be finite");
}

// The word arguments that name something: live's on/off, a view mode, a baseline.
void checkText(const ScriptCommand& c, const std::string& where) {
    if (c.verb == Verb::Live && c.text != "on" && c.text != "off")
        throw UsageError(where + ": expected \"live on\" or \"live off\"");
    if (c.verb == Verb::Mode && !parseViewMode(c.text))
        throw UsageError(where + ": \"" + c.text + "\" is not a view mode");
    if (c.verb == Verb::Baseline && !isViewerBaseline(c.text))
        throw UsageError(where + ": baseline \"" + c.text + "\": expected gtao, hbao or alchemy");
}

}  // namespace

const char* verbName(Verb verb) { return kGrammar[int(verb)].name; }

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
        std::string verb = w[0];
        for (char& ch : verb) ch = char(std::tolower(static_cast<unsigned char>(ch)));
        const Grammar* g = nullptr;
        for (const Grammar& candidate : kGrammar)
            if (verb == candidate.name) g = &candidate;
        if (!g) {
            std::string verbs;
            for (const Grammar& candidate : kGrammar) verbs += std::string(verbs.empty() ? "" : ", ") + candidate.name;
            throw UsageError(where + ": unknown command \"" + w[0] + "\"; expected one of " + verbs);
        }
        const std::size_t expected = std::size_t(g->numbers) + (g->text ? 1 : 0);
        c.verb = g->verb;
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
        checkNumbers(c, where);
        checkText(c, where);
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
