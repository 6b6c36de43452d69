#include "cover/model/info.h"

#include "cover/field/field.h"
#include "cover/solid/errors.h"
#include "cover/solid/solid.h"

namespace cover {

ModelInfo info(const Model& model, const InfoOptions& options) {
  ModelInfo out;
  if (model.empty()) return out;
  const Solid& s = model.solid();
  out.vertices = s.vertices.size();
  out.faces = s.face_count();
  out.bbox = s.bbox();
  ValidateOptions vo;
  vo.check_self_intersection = options.check_self_intersection;
  out.leaves.reserve(s.leaves.size());
  for (uint32_t l = 0; l < s.leaves.size(); ++l) {
    const Leaf& leaf = s.leaves[l];
    LeafInfo li;
    li.name = leaf.name;
    li.origin = leaf.origin;
    li.vertices = leaf.vertex_count;
    li.faces = leaf.face_count;
    li.bbox = leaf.bbox;
    if (leaf.is_field()) {
      li.field = s.fields[leaf.field];
      li.threshold = field::threshold(*li.field);
      out.leaves.push_back(std::move(li));
      continue;
    }
    if (leaf.is_warp()) {
      li.warp = s.warps[leaf.warp];
      li.child_leaves = li.warp->child->leaves.size();
      out.leaves.push_back(std::move(li));
      continue;
    }
    const PolygonMesh mesh = leaf_mesh(s, l);
    li.report = validate_mesh(mesh, vo);
    try {
      li.brep = brep::validate(brep::HalfedgeMesh::from_polygon_mesh(mesh));
    } catch (const InputError&) {  // not an oriented surface: the kernel cannot hold it
      li.brep = std::nullopt;
    }
    li.repair = repair_report(mesh, li.report);
    out.leaves.push_back(std::move(li));
  }
  return out;
}

}  // namespace cover
