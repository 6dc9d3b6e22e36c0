#include <gtest/gtest.h>
TEST(VulkanConsumer, Placeholder) {}
