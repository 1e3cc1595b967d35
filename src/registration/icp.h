#pragma once
// A view's ICP cloud with a k-d tree over its points, made once and used by every pair the
// view is in as the fixed cloud (private to the library; checkIcp in registration.h).

#include "core/kd_tree.h"

#include <scanplan/registration/registration.h>

namespace scanplan::detail {

struct IndexedCloud {
  explicit IndexedCloud(IcpCloud made);
  IndexedCloud(const IndexedCloud&) = delete;  // the tree refers to `cloud`
  IndexedCloud& operator=(const IndexedCloud&) = delete;

  IcpCloud cloud;
  PointCloudAdaptor adaptor{cloud.points};
  PointTree tree;
};

// checkIcp with `fixed` indexed beforehand.
IcpCheck checkIcp(const Simulator& simulator, const IndexedCloud& fixed, const IcpCloud& moved,
                  const RegistrationOptions& options);

}  // namespace scanplan::detail
