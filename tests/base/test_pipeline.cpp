// parallel_prepared (base/pipeline.cpp): every body after its own step, steps in order, errors.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <vector>

#include "base/pipeline.hpp"

namespace fdmsurf::detail {
namespace {

TEST(ParallelPrepared, EachBodyRunsOnceAfterItsStep) {
    for (unsigned threads : {1u, 2u, 4u}) {
        for (std::size_t count : {std::size_t{0}, std::size_t{1}, std::size_t{3}, std::size_t{500}}) {
            // A vector grown one item a step (as the structure readers grow theirs), the bodies
            // writing through a pointer taken before.
            std::vector<int> grown;
            grown.reserve(count);
            int* const data = grown.data();
            std::vector<std::size_t> steps;  // written by the preparing thread alone
            std::vector<std::atomic<int>> runs(count);
            std::atomic<bool> early{false};
            parallel_prepared(
                count, threads,
                [&](std::size_t i) {
                    steps.push_back(i);
                    grown.push_back(-1);
                },
                [&](std::size_t i) {
                    if (data[i] != -1) early = true;  // the step's value must be there
                    data[i] = int(i);
                    ++runs[i];
                });
            ASSERT_EQ(steps.size(), count);
            for (std::size_t i = 0; i < count; ++i) {
                EXPECT_EQ(steps[i], i);
                EXPECT_EQ(runs[i], 1) << i;
                EXPECT_EQ(grown[i], int(i));
            }
            EXPECT_FALSE(early) << threads << " threads, " << count << " items";
        }
    }
}

TEST(ParallelPrepared, RethrowsTheErrorOfAStepOrABody) {
    for (unsigned threads : {1u, 2u, 4u}) {
        std::atomic<int> bodies{0};
        EXPECT_THROW(parallel_prepared(
                         100, threads,
                         [](std::size_t i) {
                             if (i == 40) throw std::runtime_error("step");
                         },
                         [&](std::size_t) { ++bodies; }),
                     std::runtime_error);
        EXPECT_LE(bodies, 40);  // none of the items whose step did not run
        EXPECT_THROW(parallel_prepared(
                         100, threads, [](std::size_t) {},
                         [](std::size_t i) {
                             if (i == 7) throw std::runtime_error("body");
                         }),
                     std::runtime_error);
    }
}

}  // namespace
}  // namespace fdmsurf::detail
