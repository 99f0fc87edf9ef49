// cubeao info SCENE [--json]: what was loaded, what was repaired.
#include <cstdio>

#include "commands.h"
#include "cubeao/scene/import.h"

namespace cubeao::cli {

void addInfo(CLI::App& app) {
    auto* cmd = app.add_subcommand("info", "Describe a scene (triangles, bounding box, problems repaired on load)");
    auto spec = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    cmd->add_option("scene", *spec, "Model file (OBJ/PLY/OFF/STL/IFC/glTF/FBX/3DS/DAE) or builtin:NAME")->required();
    cmd->add_flag("--json", *json, "Print one JSON object as the last line");
    cmd->callback([spec, json] {
        const Scene s = loadScene(*spec);
        const auto& b = s.bounds;
        std::printf("%s\n  triangles  %zu\n  vertices   %zu\n  bbox       (%g, %g, %g) -> (%g, %g, %g)\n"
                    "  hash       %s\n  radius     %g (default: 2%% of the diagonal)\n"
                    "  repaired   %zu zero-area triangles, %zu duplicate vertices, %zu unused vertices%s\n",
                    s.source.c_str(), s.triangleCount(), s.vertexCount(), b.min.x, b.min.y, b.min.z, b.max.x,
                    b.max.y, b.max.z, hashToString(s.hash).c_str(), s.defaultRadius(), s.problems.degenerateTriangles,
                    s.problems.duplicateVertices, s.problems.unusedVertices,
                    s.problems.normalsComputed ? "; normals computed" : "");
        if (!s.problems.warnings.empty())
            std::printf("  importer   %zu warnings (first: %s)\n", s.problems.warnings.size(),
                        s.problems.warnings.front().c_str());
        if (!*json) return;
        printJson({{"scene", s.source},
                   {"triangles", s.triangleCount()},
                   {"vertices", s.vertexCount()},
                   {"bbox", {{"min", {b.min.x, b.min.y, b.min.z}}, {"max", {b.max.x, b.max.y, b.max.z}}}},
                   {"up", {s.up.x, s.up.y, s.up.z}},
                   {"hash", hashToString(s.hash)},
                   {"default_radius", s.defaultRadius()},
                   {"problems", s.problems.toJson()}});
    });
}

}  // namespace cubeao::cli
