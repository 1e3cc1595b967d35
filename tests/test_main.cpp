#include <gtest/gtest.h>

#include <Message.hxx>
#include <Message_Messenger.hxx>

int main(int argc, char** argv) {
  // Keep OCCT's reader statistics out of the test log.
  Message::DefaultMessenger()->ChangePrinters().Clear();
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
