// Runs several QTest objects in one binary: the test functions named on the command line go to
// the object that has them (none named: every object runs all of its own).
#pragma once

#include <QByteArray>
#include <QObject>
#include <QSet>
#include <QTest>

#include <algorithm>
#include <cstring>
#include <vector>

namespace glint::studio::testing {

inline int runTests(const std::vector<QObject*>& tests, int argc, char** argv) {
    // QTest options followed by a value (not a test function name).
    static const QSet<QByteArray> withValue = {
        "-o",    "-maxwarnings", "-eventdelay", "-keydelay",     "-mousedelay",   "-platform",
        "-seed", "-iterations",  "-median",     "-minimumvalue", "-minimumtotal", "-repeat"};
    std::vector<int> functions;  // argv indices of test function names
    for (int i = 1; i < argc; ++i) {
        if (argv[i][0] == '-') {
            if (withValue.contains(QByteArray(argv[i]))) ++i;
            continue;
        }
        functions.push_back(i);
    }
    int status = 0;
    for (QObject* test : tests) {
        std::vector<char*> args{argv[0]};
        bool named = false;
        for (int i = 1; i < argc; ++i) {
            const bool function =
                std::find(functions.begin(), functions.end(), i) != functions.end();
            if (function) {
                // "name" or "name:tag": this object's when it has the slot.
                QByteArray name(argv[i]);
                name = name.left(name.indexOf(':') < 0 ? name.size() : name.indexOf(':'));
                if (test->metaObject()->indexOfMethod(name + "()") < 0) continue;
                named = true;
            }
            args.push_back(argv[i]);
        }
        if (!functions.empty() && !named) continue;
        status |= QTest::qExec(test, int(args.size()), args.data());
    }
    return status;
}

}  // namespace glint::studio::testing
