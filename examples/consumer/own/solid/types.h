#pragma once
// The consumer's own "solid/types.h", first on its include path: Cover's installed headers must
// not pick it up in place of their own (they include "cover/solid/types.h").
namespace consumer {
struct Vec3 {
  float x, y, z;
};
}  // namespace consumer
