#include <gtest/gtest.h>
TEST(Stress, Placeholder) {}
