#include <artemis/core/transform.hpp>

#include <cstdio>

int main() {
  artemis::Isometry3d T = artemis::Isometry3d::Identity();
  T.translation() << 1.0, 2.0, 3.0;
  const auto back = artemis::isometryFromRowMajor3x4(artemis::toRowMajor3x4(T.inverse()));
  if (!back.isOk()) return 1;
  const double x = back->translation().x();
  std::printf("inverse translation x = %.1f\n", x);
  return x == -1.0 ? 0 : 1;
}
