// Chandrasekhar's H function (lib/analysis/study/chandrasekhar_h.h): the analytic anchor of issue 21's
// semi-infinite tests. Checked against published values and exact identities, none of which the
// solver uses.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/study/chandrasekhar_h.h"
#include "core/error.h"

using namespace vpm;

// Chandrasekhar, Radiative Transfer (1950), table XI (conservative isotropic scattering):
// H(1) = 2.90781, H(0.5) = 2.01278, H(0) = 1.
TEST(ChandrasekharH, ConservativeTableValues) {
    const ChandrasekharH h(1.0);
    EXPECT_NEAR(h(1.0), 2.90781, 1e-5);
    EXPECT_NEAR(h(0.5), 2.01278, 1e-5);
    EXPECT_DOUBLE_EQ(h(0.0), 1.0);
}

// Moments: int_0^1 H = (2 / a) (1 - sqrt(1 - a)) for every albedo, and int_0^1 H mu = 2 / sqrt(3)
// when a = 1; the solution does not move when the quadrature doubles (1e-8, the target).
TEST(ChandrasekharH, MomentIdentitiesAndConvergence) {
    for (double a : {0.1, 0.5, 0.9, 0.99, 0.999, 1.0}) {
        const ChandrasekharH h(a), fine(a, 192);
        EXPECT_NEAR(h.moment(0), 2.0 / a * (1.0 - std::sqrt(1.0 - a)), 1e-10) << a;
        for (double mu : {0.01, 0.1, 0.5, 1.0}) EXPECT_NEAR(h(mu), fine(mu), 1e-9) << a << " " << mu;
    }
    EXPECT_NEAR(ChandrasekharH(1.0).moment(1), 2.0 / std::sqrt(3.0), 1e-10);
}

// The closed form: the values the issue measured with the path tracer (albedo 0.9 and 0.99, normal
// incidence and view), single scattering a / (4 pi) mu0 / (mu + mu0), reciprocity of L / mu0.
TEST(ChandrasekharH, ReflectedRadiance) {
    EXPECT_NEAR(ChandrasekharH(0.9).reflected(1.0, 1.0), 0.122572, 1e-6);
    EXPECT_NEAR(ChandrasekharH(0.99).reflected(1.0, 1.0), 0.240863, 1e-6);
    const ChandrasekharH h(0.7);
    EXPECT_DOUBLE_EQ(h.single_scattering(0.5, 1.0), 0.7 / (4.0 * M_PI) / 1.5);
    EXPECT_NEAR(h.reflected(0.3, 0.8) / 0.8, h.reflected(0.8, 0.3) / 0.3, 1e-14);   // the BRDF L / (E mu0) is symmetric
    EXPECT_GT(h.reflected(0.5, 1.0), h.single_scattering(0.5, 1.0));
}

TEST(ChandrasekharH, BadInputIsAnError) {
    EXPECT_THROW(ChandrasekharH(1.5), Error);
    EXPECT_THROW(ChandrasekharH(-0.1), Error);
    EXPECT_THROW(ChandrasekharH(0.5, 4), Error);
    EXPECT_THROW(ChandrasekharH(0.5)(1.5), Error);
}
