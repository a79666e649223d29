#include "scene/gltf_nodes.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

namespace ddgi {
namespace {

std::string node_name(size_t index) {
  return "nodes[" + std::to_string(index) + "]";
}

// glTF 2.0 section 3.5.3: the matrix when given, else T * R * S. Doubles, so that deep
// hierarchies lose no precision before the final conversion.
Result<glm::dmat4> local_transform(const tinygltf::Node& node, size_t index) {
  glm::dmat4 m(1.0);
  if (node.matrix.size() == 16) {
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) m[c][r] = node.matrix[static_cast<size_t>(c * 4 + r)];
    }
    return m;
  }
  if (node.translation.size() == 3) {
    m = glm::translate(m,
                       glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
  }
  if (node.rotation.size() == 4) {
    glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
    const double length = glm::length(q);
    if (!(length > 1e-12)) {
      return invalid_argument(node_name(index) + ".rotation is a zero quaternion");
    }
    m *= glm::mat4_cast(q / length);
  }
  if (node.scale.size() == 3) {
    m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
  }
  return m;
}

// parent[n]: the node listing n as a child, -1 for roots. Fails on a second parent.
Result<std::vector<int>> find_parents(const tinygltf::Model& model) {
  std::vector<int> parent(model.nodes.size(), -1);
  for (size_t p = 0; p < model.nodes.size(); ++p) {
    for (int child : model.nodes[p].children) {
      const size_t c = static_cast<size_t>(child);
      if (c == p) return invalid_argument(node_name(p) + " lists itself as a child (a cycle)");
      if (parent[c] == static_cast<int>(p)) {
        return invalid_argument(node_name(p) + ".children lists " + node_name(c) + " twice");
      }
      if (parent[c] != -1) {
        return invalid_argument(node_name(c) + " has two parents (" +
                                node_name(static_cast<size_t>(parent[c])) + " and " + node_name(p) +
                                "); glTF nodes must form a tree");
      }
      parent[c] = static_cast<int>(p);
    }
  }
  return parent;
}

// With at most one parent each, a node is on a cycle exactly when no root reaches it.
Status check_no_cycles(const tinygltf::Model& model, const std::vector<int>& parent) {
  std::vector<bool> reached(model.nodes.size(), false);
  std::vector<size_t> stack;
  for (size_t n = 0; n < model.nodes.size(); ++n) {
    if (parent[n] == -1) stack.push_back(n);
  }
  while (!stack.empty()) {
    const size_t n = stack.back();
    stack.pop_back();
    reached[n] = true;
    for (int child : model.nodes[n].children) stack.push_back(static_cast<size_t>(child));
  }
  for (size_t n = 0; n < model.nodes.size(); ++n) {
    if (!reached[n]) {
      return invalid_argument(node_name(n) + " is part of a cycle in the node hierarchy");
    }
  }
  return ok_status();
}

Result<std::vector<int>> scene_roots(const tinygltf::Model& model, const std::vector<int>& parent,
                                     std::vector<std::string>* warnings) {
  std::vector<int> roots;
  if (model.scenes.empty()) {
    for (size_t n = 0; n < model.nodes.size(); ++n) {
      if (parent[n] == -1) roots.push_back(static_cast<int>(n));
    }
    if (!roots.empty()) warnings->push_back("the file has no scenes; every root node is used");
    return roots;
  }
  const size_t s = model.defaultScene >= 0 ? static_cast<size_t>(model.defaultScene) : 0;
  const std::string where = "scenes[" + std::to_string(s) + "].nodes";
  std::vector<bool> listed(model.nodes.size(), false);
  for (int root : model.scenes[s].nodes) {
    const size_t r = static_cast<size_t>(root);
    if (parent[r] != -1) {
      return invalid_argument(where + " lists " + node_name(r) + ", which is a child of " +
                              node_name(static_cast<size_t>(parent[r])));
    }
    if (listed[r]) return invalid_argument(where + " lists " + node_name(r) + " twice");
    listed[r] = true;
    roots.push_back(root);
  }
  return roots;
}

}  // namespace

Result<std::vector<PlacedNode>> place_nodes(const tinygltf::Model& model, const SceneLimits& limits,
                                            std::vector<std::string>* warnings) {
  DDGI_ASSIGN_OR_RETURN(const std::vector<int> parent, find_parents(model));
  DDGI_TRY(check_no_cycles(model, parent));
  DDGI_ASSIGN_OR_RETURN(const std::vector<int> roots, scene_roots(model, parent, warnings));

  struct Pending {
    size_t node;
    glm::dmat4 parent_world;
    uint32_t depth;
  };
  std::vector<Pending> stack;
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) {
    stack.push_back({static_cast<size_t>(*it), glm::dmat4(1.0), 1});
  }
  std::vector<PlacedNode> placed;
  while (!stack.empty()) {
    const Pending item = stack.back();
    stack.pop_back();
    if (item.depth > limits.max_node_depth) {
      return resource_exhausted("the node hierarchy is deeper than " +
                                std::to_string(limits.max_node_depth) + " levels (at " +
                                node_name(item.node) + ")");
    }
    const tinygltf::Node& node = model.nodes[item.node];
    DDGI_ASSIGN_OR_RETURN(const glm::dmat4 local, local_transform(node, item.node));
    const glm::dmat4 world = item.parent_world * local;
    const glm::mat4 world_f(world);
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) {
        if (!std::isfinite(world_f[c][r])) {
          return invalid_argument(node_name(item.node) +
                                  ": the world transform is not finite (it overflows)");
        }
      }
    }
    placed.push_back({static_cast<int>(item.node), world_f});
    for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) {
      stack.push_back({static_cast<size_t>(*it), world, item.depth + 1});
    }
  }
  return placed;
}

}  // namespace ddgi
