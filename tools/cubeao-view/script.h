// The viewer's script language (`cubeao-view --script FILE`): one command a line, `#` starts a comment.
// A script drives the viewer for tests and demos exactly as a person would (it moves the camera,
// switches modes, waits frames, takes screenshots, saves, quits); the window is real and every frame
// renders. Parsed completely before the window opens, so a typo fails at once with its line number.
//
//   frames N              render N frames with nothing changed (waiting for streaming, bakes, …)
//   path F                jump to frame F of --camera (the camera exactly as `cubeao render` has it)
//   play A B              follow frames A..B-1 of --camera, one per rendered frame
//   eye X Y Z             put the camera at a world point, keeping its direction
//   look X Y Z            turn the camera towards a world point
//   move R U F            move along the camera's right, up and forward axes (world units)
//   turn YAW PITCH        turn by degrees (positive: left, up)
//   walk R U F N          move by (R, U, F) split over N frames (a walk, rendered frame by frame)
//   size W H              render at W × H pixels (default: the window's size times --scale)
//   mode NAME             a view mode (view_modes.h: shaded, ao, probe, footprint, confidence, path, baseline, diff)
//   baseline NAME         the screen-space baseline the baseline mode shows: gtao, hbao or alchemy
//   live on|off           live placement (needs the scene's placement; see viewer.h)
//   idle N                N frames counted as idle (no input): the live placement re-bakes with traced then
//   settle N              render frames until live placement has baked every probe it placed (at most N)
//   rebake N              idle frames until live placement has re-baked every probe with traced (at most N)
//   screenshot FILE       FILE.png: the view as shown (no panel); FILE.exr: the AO of the current method, linear
//   screenshot-window F   the whole window with the panel, PNG
//   save FILE             write the probes (live placement's, else the opened cache's) atomically
//   record FILE | record stop   record the camera to a camera-path JSON from now on / stop and write it
//   quit                  end the script and the viewer (also implied at the end of the file)
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace cubeao::viewer {

enum class Verb {
    Frames, Path, Play, Eye, Look, Move, Turn, Walk, Size, Mode, Baseline, Live, Idle, Settle, Rebake,
    Screenshot, ScreenshotWindow, Save, Record, Quit
};
const char* verbName(Verb verb);  // as the script spells it

struct ScriptCommand {
    Verb verb = Verb::Quit;
    std::vector<double> numbers;       // numeric arguments
    std::string text;                  // the file, mode, baseline or on/off argument (names already checked)
    int line = 0;                      // 1-based line in the script, for messages
};

// Every command of `text`; throws cubeao::UsageError naming `source`, the line and what was expected
// (unknown verbs, argument counts, numbers out of range, unknown view modes and baselines).
std::vector<ScriptCommand> parseScript(const std::string& text, const std::string& source = "script");
std::vector<ScriptCommand> readScript(const std::filesystem::path& file);

}  // namespace cubeao::viewer
