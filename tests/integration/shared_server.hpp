// A test suite that shares one running server: started before its first
// test with Derived::Args() (and Derived::Binary(), the release server unless
// the suite names another), stopped after its last.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "server_process.hpp"

namespace surfdeform::testing {

template <typename Derived>
class SharedServerTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    server_ = std::make_unique<ServerProcess>(Derived::Binary(), Derived::Args());
    ASSERT_GT(server_->port(), 0) << "the server (" << Derived::Binary() << ") did not start";
  }
  static void TearDownTestSuite() { server_.reset(); }
  static std::string Binary() { return ServerBinary(); }
  static int port() { return server_->port(); }

  static inline std::unique_ptr<ServerProcess> server_;
};

}  // namespace surfdeform::testing
