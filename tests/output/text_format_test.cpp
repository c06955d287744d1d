// PutGeneral writes what a stream writes at the same precision in its default notation.
#include "output/text_format.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <sstream>
#include <vector>

namespace dslam {
namespace {

std::string ByStream(double value, int digits) {
  std::ostringstream s;
  s << std::setprecision(digits) << value;
  return s.str();
}

std::string ByPutGeneral(double value, int digits) {
  std::ostringstream s;
  PutGeneral(s, value, digits);
  return s.str();
}

TEST(TextFormat, PutGeneralWritesWhatTheStreamWrites) {
  std::vector<double> values = {0.0, -0.0, 1.0, -1.0, 0.1, 123456789.0, 1234567890123.0, 1e-7, 1e-5, 0.0001,
                                0.00012345678912, 7.90004731, 1e300, -1e-300, 4.9e-324,
                                std::numeric_limits<double>::max(), std::numeric_limits<double>::infinity(),
                                -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()};
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-12, 12);
  for (int i = 0; i < 20000; ++i) values.push_back(mantissa(random) * std::pow(10.0, exponent(random)));
  for (const int digits : {1, 6, 9, 17, 25})
    for (const double v : values) ASSERT_EQ(ByPutGeneral(v, digits), ByStream(v, digits)) << v << " at " << digits;
  std::ostringstream s;
  s << std::setprecision(4);
  PutGeneral(s, 1.0 / 3.0, 25);
  s << ' ' << 1.0 / 3.0;
  EXPECT_EQ(s.str().substr(s.str().find(' ')), " 0.3333");  // the stream's own precision is left as it was
}

}  // namespace
}  // namespace dslam
