// --display-server HOST:PORT: streams the render's snapshots to a running tev over TCP
// (tev_protocol.h), on a thread of its own, about four times a second: CreateImage with
// channels R, G, B once per connection, then UpdateImage for each 128 x 128 tile and
// channel whose values changed since the last frame sent. The render never waits on it:
// the thread reads the newest snapshot (ViewHub) and skips the frames it is too slow for;
// its socket operations time out. A server that is not there, goes away or stops reading
// is a warning, and the thread reconnects every second (a restarted tev gets the image
// again). In the interactive mode it streams every render of the session (ViewHub::
// sessionRunning) and the image written at its end.
#pragma once
#include <memory>
#include <string>

#include "app/view_hub.h"

namespace wmlt {

class TevSender {
public:
    // Resolves `host` at once: throws InputError (exit status 2) when it cannot. Nothing
    // is sent until the thread connects.
    TevSender(ViewHub& hub, const std::string& host, const std::string& port, std::string imageName, bool quiet);
    ~TevSender();  // stops the thread (it does not wait for the final frame)
    // After hub.finish(): returns once the final frame is sent, or given up on after two
    // tries (at once when nothing listens; within seconds when the server is stalled).
    void waitFinalSent();

private:
    struct Thread;
    std::unique_ptr<Thread> thread_;
};

}  // namespace wmlt
