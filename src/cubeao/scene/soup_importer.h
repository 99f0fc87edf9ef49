// An OpenMesh importer that keeps the file's triangles as a soup. OpenMesh's own TriMesh importer
// builds half-edge connectivity: every non-manifold face ("complex edge/vertex", hundreds on
// Sibenik) is re-added with duplicated vertices or, where even that fails, dropped, with a line of
// stderr for each. Architecture models are non-manifold by nature and AO needs no connectivity, so
// OpenMesh's readers parse and we keep every face as the file wrote it.
#pragma once

#include <OpenMesh/Core/IO/importer/BaseImporter.hh>

#include <unordered_map>
#include <vector>

#include <glm/vec3.hpp>

namespace cubeao {

class SoupImporter final : public OpenMesh::IO::BaseImporter {
public:
    std::vector<glm::vec3> positions, normals;  // normals: one per vertex when the file had them
    std::vector<std::uint32_t> indices;          // polygons fan-triangulated
    // Per position: the file vertex (in add_vertex order) it is, or copies after a corner split. The
    // readers parse coordinates into float; import.cpp puts its own double parse of the file back through
    // this map (georeferenced models, Scene::origin).
    std::vector<std::uint32_t> fileVertex;
    std::size_t faces = 0;                       // polygons as the file wrote them
    bool hasNormals = false;

    using VH = OpenMesh::VertexHandle;
    using HH = OpenMesh::HalfedgeHandle;
    using FH = OpenMesh::FaceHandle;
    using EH = OpenMesh::EdgeHandle;
    using Vec2f = OpenMesh::Vec2f;
    using Vec3f = OpenMesh::Vec3f;
    using Vec3d = OpenMesh::Vec3d;
    using Vec4f = OpenMesh::Vec4f;
    using Vec3uc = OpenMesh::Vec3uc;
    using Vec4uc = OpenMesh::Vec4uc;
    using Status = OpenMesh::Attributes::StatusInfo;

    VH add_vertex(const Vec3f& p) override {
        fileVertex.push_back(std::uint32_t(fileVertices()));
        positions.emplace_back(p[0], p[1], p[2]);
        normals.emplace_back(0.0f);
        return VH(int(positions.size() - 1));
    }
    VH add_vertex() override { return add_vertex(Vec3f(0.0f, 0.0f, 0.0f)); }
    FH add_face(const VHandles& v) override {
        // Out-of-range handles are kept as they are: validateMesh reports them with the file name.
        auto index = [&](VH h) {
            const auto it = cornerSplit_.find(h.idx());
            return std::uint32_t(it == cornerSplit_.end() ? h.idx() : it->second);
        };
        for (std::size_t i = 1; i + 1 < v.size(); ++i)
            indices.insert(indices.end(), {index(v[0]), index(v[i]), index(v[i + 1])});
        cornerSplit_.clear();
        return FH(int(faces++));
    }
    // OBJ normals belong to face corners: the reader sets each corner's normal on the vertex just
    // before add_face. A vertex that already has a different normal (a hard edge) is split: the face
    // gets a copy of the position carrying its own normal.
    void set_normal(VH vh, const Vec3f& n) override {
        if (vh.idx() < 0 || std::size_t(vh.idx()) >= normals.size()) return;
        const auto i = std::size_t(vh.idx());
        const glm::vec3 normal(n[0], n[1], n[2]);
        if (normalSet_.size() < normals.size()) normalSet_.resize(normals.size(), false);
        if (normalSet_[i] && normals[i] != normal) {
            positions.push_back(positions[i]);
            fileVertex.push_back(fileVertex[i]);
            normals.push_back(normal);
            normalSet_.push_back(true);
            cornerSplit_[vh.idx()] = int(positions.size() - 1);
            ++copies_;
        } else {
            normals[i] = normal;
            normalSet_[i] = true;
        }
        hasNormals = true;
    }
    // Vertices the file wrote (`v` lines), without the copies made for split corners.
    std::size_t fileVertices() const { return positions.size() - copies_; }
    void set_normal(VH vh, const Vec3d& n) override { set_normal(vh, Vec3f(n)); }
    void set_point(VH vh, const Vec3f& p) override {
        if (vh.idx() >= 0 && std::size_t(vh.idx()) < positions.size())
            positions[std::size_t(vh.idx())] = glm::vec3(p[0], p[1], p[2]);
    }
    size_t n_vertices() const override { return fileVertices(); }
    size_t n_faces() const override { return faces; }
    size_t n_edges() const override { return 0; }

    // Connectivity, colours, texture coordinates and status are of no use to AO.
    HH add_edge(VH, VH) override { return HH(); }
    FH add_face(HH) override { return FH(); }
    void add_face_texcoords(FH, VH, const std::vector<Vec2f>&) override {}
    void add_face_texcoords(FH, VH, const std::vector<Vec3f>&) override {}
    void set_face_texindex(FH, int) override {}
    void set_halfedge(VH, HH) override {}
    void set_color(VH, const Vec3uc&) override {}
    void set_color(VH, const Vec4uc&) override {}
    void set_color(VH, const Vec3f&) override {}
    void set_color(VH, const Vec4f&) override {}
    void set_texcoord(VH, const Vec2f&) override {}
    void set_status(VH, const Status&) override {}
    void set_next(HH, HH) override {}
    void set_face(HH, FH) override {}
    void request_face_texcoords2D() override {}
    void set_texcoord(HH, const Vec2f&) override {}
    void set_texcoord(VH, const Vec3f&) override {}
    void set_texcoord(HH, const Vec3f&) override {}
    void set_status(HH, const Status&) override {}
    void set_color(EH, const Vec3uc&) override {}
    void set_color(EH, const Vec4uc&) override {}
    void set_color(EH, const Vec3f&) override {}
    void set_color(EH, const Vec4f&) override {}
    void set_status(EH, const Status&) override {}
    void set_normal(FH, const Vec3f&) override {}
    void set_normal(FH, const Vec3d&) override {}
    void set_color(FH, const Vec3uc&) override {}
    void set_color(FH, const Vec4uc&) override {}
    void set_color(FH, const Vec3f&) override {}
    void set_color(FH, const Vec4f&) override {}
    void set_status(FH, const Status&) override {}
    void add_texture_information(int, std::string) override {}

private:
    std::vector<bool> normalSet_;
    std::unordered_map<int, int> cornerSplit_;  // this face's corners: vertex → its split copy
    std::size_t copies_ = 0;  // positions appended by set_normal's splits
};

}  // namespace cubeao
