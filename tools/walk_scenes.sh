# Sourced by tools/walks.sh and tools/bench_place.sh: the shared walks (../shared/scenes/README.md).
# walk_scene NAME CALLER: sets `scene` (model file) and `walk` (camera path) for sibenik or fzk-haus,
# exits 2 naming CALLER for anything else and 1 when the model is missing.
walk_scene() {
  local shared
  shared=$(realpath ../shared)
  case $1 in
    sibenik) scene=$shared/scenes/sibenik/sibenik.obj; walk=$shared/scenes/sibenik/walk.json ;;
    fzk-haus) scene=/usr/share/assimp/models/IFC/AC14-FZK-Haus.ifc; walk=$shared/scenes/fzk-haus/walk.json ;;
    *) echo "$2: unknown walk \"$1\" (sibenik or fzk-haus)" >&2; exit 2 ;;
  esac
  [ -f "$scene" ] || { echo "$2: $scene is missing (see ../shared/scenes/README.md)" >&2; exit 1; }
}
