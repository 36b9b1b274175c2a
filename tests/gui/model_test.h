// The studio's model tests beyond the user workflow, run by studio_test.cpp's main.
#pragma once

#include <QObject>

#include <memory>

/// The bank service's tests (model_test.cpp).
std::unique_ptr<QObject> makeStudioModelTest();
/// Auto Start on a Cycles frame (auto_start_test.cpp).
std::unique_ptr<QObject> makeStudioAutoStartTest();
