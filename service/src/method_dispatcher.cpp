#include "method_dispatcher.h"

#include <thread>

#include "core/base64.h"
#include "json_fields.h"
#include "service/catalog_json.h"
#include "service/plan_result_json.h"
#include "service/ros_messages.h"

namespace hfts::service {

using nlohmann::json;

namespace {

int workerCount(int requested) {
  if (requested < 0) throw std::invalid_argument("workers must be >= 0 (0: one per core)");
  if (requested > 0) return requested;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

void noParams(const Call& call) {
  JsonFields(call.params, "").allowOnly({});
}

/// The params of a listing that may name a robot ({"robot": name}).
const CatalogRobot& listedRobot(const Call& call, const PlanningCatalog& catalog) {
  JsonFields(call.params, "").allowOnly({"robot"});
  return requestedRobot(call.params, catalog);
}

}  // namespace

MethodDispatcher::MethodDispatcher(const ServerOptions& options,
                                   std::shared_ptr<const PlanningCatalog> catalog,
                                   std::shared_ptr<const TokenTable> tokens, PostToIo post,
                                   PostAfter postAfter, std::function<void()> onShutdown)
    : options_(options),
      limits_{options.max_time_limit, workerCount(options.workers)},
      catalog_(std::move(catalog)),
      tokens_(std::move(tokens)),
      post_(std::move(post)),
      post_after_(std::move(postAfter)),
      on_shutdown_(std::move(onShutdown)),
      log_(options.log),
      pool_(workerCount(options.workers), options.queue_capacity),
      quality_pool_(1, options.queue_capacity),
      methods_{{"auth", &MethodDispatcher::auth},
               {"server.info", &MethodDispatcher::info},
               {"objects.list", &MethodDispatcher::objects},
               {"scenes.list", &MethodDispatcher::scenes},
               {"grasp.quality", &MethodDispatcher::quality},
               {"plan", &MethodDispatcher::plan},
               {"cancel", &MethodDispatcher::cancel},
               {"shutdown", &MethodDispatcher::shutdown},
               {"reload", &MethodDispatcher::reload}} {
  if (!(options.max_time_limit > 0)) throw std::invalid_argument("max time limit must be > 0");
}

MethodDispatcher::~MethodDispatcher() {
  if (reload_thread_.joinable()) reload_thread_.join();
}

void MethodDispatcher::dispatch(const Call& call, const Caller& caller, Responder respond) {
  ++calls_;
  const auto began = std::chrono::steady_clock::now();
  // The reply needs the id and the method, not the params (which may be large).
  Finish finish = [this, id = call.id, notification = call.notification, method = call.method,
                   peer = caller.peer, began, respond = std::move(respond)](Outcome o) {
    log_.write(peer, notification ? "-" : id.dump(), method,
               std::chrono::steady_clock::now() - began,
               o.error ? describe(*o.error) : "ok" + (o.note.empty() ? "" : " " + o.note));
    if (notification)
      respond(json());
    else
      respond(o.error ? errorResponse(id, *o.error) : resultResponse(id, std::move(o.result)));
  };
  try {
    const auto method = methods_.find(call.method);
    if (method == methods_.end())
      throw RpcError(ErrorCode::kMethodNotFound, "method not found: '" + call.method + "'");
    checkAccess(call.method, caller);
    if (stopping_ && call.method != "cancel")
      throw RpcError(ErrorCode::kShuttingDown, "the server is shutting down");
    (this->*(method->second))(call, caller, finish);
  } catch (const RpcError& e) {
    finish({json(), e, ""});
  } catch (const std::exception& e) {
    finish({json(), RpcError(ErrorCode::kInternalError, std::string("internal error: ") + e.what()),
            ""});
  }
}

void MethodDispatcher::logRejected(const Caller& caller, const json& errorResponse) const {
  const json& error = errorResponse.at("error");
  log_.write(caller.peer, errorResponse.at("id").dump(), "-",
             std::chrono::steady_clock::duration::zero(),
             "error " + error.at("code").dump() + " " + error.at("message").get<std::string>());
}

std::string MethodDispatcher::describe(const RpcError& error) {
  return "error " + std::to_string(static_cast<int>(error.code())) + " " + error.what();
}

void MethodDispatcher::stop() {
  stopping_ = true;
  pool_.cancelAll();
  quality_pool_.cancelAll();
}

bool MethodDispatcher::idle() const {
  return pool_.idle() && quality_pool_.idle() && !reloading_;
}

void MethodDispatcher::checkAccess(const std::string& method, const Caller& caller) const {
  const std::optional<Role> required = requiredRole(method);
  if (!tokens_ || !required) return;
  const Session& session = *caller.session;
  const TokenEntry* entry = session.token ? tokens_->find(*session.token) : nullptr;
  if (entry == nullptr)
    throw RpcError(ErrorCode::kUnauthorized,
                   session.token ? "unauthorized: this connection's token is no longer accepted "
                                   "(the server's token file changed); call auth again"
                                 : "unauthorized: call auth with a token first (docs/security.md)");
  if (!allows(entry->role, *required))
    throw RpcError(ErrorCode::kForbidden, "forbidden: " + method + " needs the " +
                                              toString(*required) + " role; this connection has " +
                                              toString(entry->role));
}

void MethodDispatcher::auth(const Call& call, const Caller& caller, const Finish& finish) {
  const JsonFields f(call.params, "");
  f.allowOnly({"token"});
  const nlohmann::json& token = f.at("token");
  if (!token.is_string()) f.fail("token", "must be a string");
  if (!tokens_) {
    finish({{{"role", toString(Role::kAdmin)}, {"authentication", false}},
            std::nullopt,
            "no tokens: every connection may call everything"});
    return;
  }
  const auto now = AuthThrottle::Clock::now();
  const TokenEntry* entry = nullptr;
  std::string refusal;
  if (const auto wait = throttle_.blockedFor(caller.address, now); wait.count() > 0) {
    const auto seconds = std::chrono::ceil<std::chrono::seconds>(wait).count();
    refusal = "unauthorized: too many failed authentications from " + caller.address +
              "; try again in " + std::to_string(seconds) + " s";
  } else if (entry = tokens_->find(token.get<std::string>()); entry == nullptr) {
    throttle_.failed(caller.address, now);
    refusal = "unauthorized: the token is not accepted; closing the connection";
  }
  if (entry == nullptr) {
    // The reply waits, then the connection closes: one guess per
    // connection and per delay, and few connections per address (throttle).
    caller.session->token.reset();
    caller.session->close_after_reply = true;
    post_after_(kAuthFailureDelay, [finish, refusal] {
      finish({nlohmann::json(), RpcError(ErrorCode::kUnauthorized, refusal), ""});
    });
    return;
  }
  caller.session->token = entry->digest;
  finish({{{"role", toString(entry->role)}, {"authentication", true}},
          std::nullopt,
          std::string("role ") + toString(entry->role) + " (" + entry->name + ")"});
}

void MethodDispatcher::info(const Call& call, const Caller&, const Finish& finish) {
  noParams(call);
  if (info_.is_null()) info_ = staticInfo();
  json result = info_;
  result["load"] = {
      {"workers", pool_.threads()},
      {"running", pool_.running()},
      {"queued", pool_.queued()},
      {"calls", calls_},
      {"uptime",
       std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count()}};
  if (connection_load_) {
    const ConnectionLoad c = connection_load_();
    result["load"]["connections"] = c.connections;
    result["load"]["input_budget_used"] = c.input_budget_used;
  }
  finish({std::move(result), std::nullopt, ""});
}

json MethodDispatcher::staticInfo() const {
  return {{"name", "hfts-server"},
          {"version", HFTS_VERSION},
          {"protocol", "JSON-RPC 2.0, one message per line"},
          {"methods",
           {"auth", "server.info", "objects.list", "scenes.list", "plan", "grasp.quality", "cancel",
            "shutdown", "reload"}},
          {"authentication", tokens_ != nullptr},
          {"tls", !options_.tls_cert.empty()},
          {"robot", robotJson(catalog_->robot())},
          {"robots", robotsJson(*catalog_)},
          {"objects", catalog_->world().objectNames().size()},
          {"scenes", catalog_->scenes().size()},
          {"planner_parameters", plannerParametersJson(catalog_->robots().front())},
          {"limits",
           {{"max_time_limit", limits_.max_time_limit},
            {"max_threads", limits_.max_threads},
            {"max_message_bytes", options_.max_message_bytes},
            {"max_connections", options_.max_connections},
            {"max_buffered_bytes", options_.max_buffered_bytes},
            {"read_timeout", options_.read_timeout},
            {"idle_timeout", options_.idle_timeout},
            {"queue_capacity", pool_.capacity()},
            {"max_plans_per_client", options_.max_plans_per_client},
            {"max_batch_calls", kMaxBatchCalls},
            {"max_nesting_depth", kMaxNestingDepth}}}};
}

void MethodDispatcher::objects(const Call& call, const Caller&, const Finish& finish) {
  finish({objectsJson(*catalog_, listedRobot(call, *catalog_)), std::nullopt, ""});
}

void MethodDispatcher::scenes(const Call& call, const Caller&, const Finish& finish) {
  finish({scenesJson(*catalog_, listedRobot(call, *catalog_)), std::nullopt, ""});
}

void MethodDispatcher::quality(const Call& call, const Caller&, const Finish& finish) {
  // Epsilon is a 6-D convex hull: milliseconds for a grasp's few contacts,
  // but seconds to minutes for dozens of contacts with many cone edges. It
  // runs on a worker of its own, so that neither the I/O thread (every
  // other connection) nor the planners wait for it.
  auto flag = std::make_shared<std::atomic<bool>>(false);
  auto job = [catalog = catalog_, params = call.params, flag, finish, post = post_] {
    auto outcome = std::make_shared<Outcome>(runQuality(*catalog, params, *flag));
    post([finish, outcome] { finish(std::move(*outcome)); });
  };
  if (!quality_pool_.trySubmit(flag, std::move(job)))
    throw RpcError(ErrorCode::kBusy, "busy: " + std::to_string(quality_pool_.capacity()) +
                                         " grasp.quality calls are waiting; try again later");
}

MethodDispatcher::Outcome MethodDispatcher::runQuality(const PlanningCatalog& catalog,
                                                       const json& params,
                                                       const std::atomic<bool>& cancel) {
  if (cancel.load())
    return {json(), RpcError(ErrorCode::kShuttingDown, "shutting down: not computed"), ""};
  try {
    json result = graspQualityJson(params, catalog);
    std::string note = "epsilon " + result["epsilon"].dump();
    return {std::move(result), std::nullopt, std::move(note)};
  } catch (const RpcError& e) {
    return {json(), e, ""};
  } catch (const std::exception& e) {
    return {json(), RpcError(ErrorCode::kInternalError, std::string("internal error: ") + e.what()),
            ""};
  }
}

std::string MethodDispatcher::clientOf(const Caller& caller) {
  const Session& session = *caller.session;
  if (session.token) return "token " + std::string(session.token->begin(), session.token->end());
  return "connection " + caller.peer;
}

void MethodDispatcher::plan(const Call& call, const Caller& caller, const Finish& finish) {
  auto request = std::make_shared<const planner::PlanRequest>(
      planRequestFromJson(call.params, *catalog_, limits_));
  const std::string client = clientOf(caller);
  const std::size_t cap = options_.max_plans_per_client;
  if (const auto held = plans_of_client_.find(client);
      cap > 0 && held != plans_of_client_.end() && held->second >= cap)
    throw RpcError(ErrorCode::kBusy,
                   "busy: this client already has " + std::to_string(cap) +
                       " plans queued or running (the server's --max-plans-per-client); wait "
                       "for one to finish");
  const planner::PlanningWorld* world = requestedRobot(call.params, *catalog_).world.get();
  const PlanExtras extras = planExtras(call.params);
  auto flag = std::make_shared<std::atomic<bool>>(false);
  const std::string key = call.id.dump();
  Finish done = [this, plans = caller.plans, key, flag, finish, client](Outcome o) {
    plans->remove(key, flag);
    if (--plans_of_client_[client] == 0) plans_of_client_.erase(client);
    finish(std::move(o));
  };
  // The catalog keeps the world alive while the plan runs.
  auto job = [catalog = catalog_, world, request, flag, done, post = post_, extras] {
    auto outcome = std::make_shared<Outcome>(runPlan(*world, *request, *flag, extras));
    post([done, outcome] { done(std::move(*outcome)); });
  };
  if (!pool_.trySubmit(flag, std::move(job), client))
    throw RpcError(ErrorCode::kBusy,
                   "busy: " + std::to_string(pool_.threads()) + " workers are planning and " +
                       std::to_string(pool_.capacity()) + " plans are waiting; try again later");
  ++plans_of_client_[client];
  caller.plans->add(key, flag);
}

MethodDispatcher::Outcome MethodDispatcher::runPlan(const planner::PlanningWorld& world,
                                                    const planner::PlanRequest& request,
                                                    const std::atomic<bool>& cancel,
                                                    const PlanExtras& extras) {
  try {
    planner::PlanResult result;
    if (cancel.load()) {  // cancelled while queued: no need to set anything up
      result.failure = planner::PlanFailure::kCancelled;
      result.message = "cancelled before it started";
      result.joint_names = world.robot().dofNames();
    } else {
      result = planner::planGrasp(world, request, &cancel);
    }
    json out = planResultToJson(result, request);
    out["robot"] = world.robot().name();
    if (extras.gltf && !result.trajectory.points.empty())
      out["gltf"] = core::base64Encode(planner::planGlb(world, request, result));
    if (extras.ros) out["ros"] = rosPlan(world, request, result);
    return {std::move(out), std::nullopt,
            result.success ? "success" : planner::toString(result.failure)};
  } catch (const InvalidArgument& e) {  // planGrasp checks parameter values
    return {json(), invalidParam(e), ""};
  } catch (const std::exception& e) {
    return {json(), RpcError(ErrorCode::kInternalError, std::string("internal error: ") + e.what()),
            ""};
  }
}

void MethodDispatcher::cancel(const Call& call, const Caller& caller, const Finish& finish) {
  const JsonFields f(call.params, "");
  f.allowOnly({"id"});
  const json& id = f.at("id");
  if (!id.is_string() && !id.is_number() && !id.is_null())
    f.fail("id", "must be the string or number id of a plan request");
  const bool found = caller.plans->cancel(id.dump());
  finish({{{"id", id}, {"cancelled", found}}, std::nullopt, found ? "cancelled" : "no such plan"});
}

void MethodDispatcher::shutdown(const Call& call, const Caller&, const Finish& finish) {
  noParams(call);
  finish({{{"shutting_down", true}}, std::nullopt, ""});
  post_(on_shutdown_);
}

void MethodDispatcher::reload(const Call& call, const Caller&, const Finish& finish) {
  noParams(call);
  if (reloading_) throw RpcError(ErrorCode::kBusy, "busy: a reload is already running");
  reloading_ = true;
  if (reload_thread_.joinable()) reload_thread_.join();
  reload_thread_ = std::thread([this, finish] {
    auto fresh = std::make_shared<Outcome>();
    std::shared_ptr<const PlanningCatalog> catalog;
    try {
      catalog = PlanningCatalog::load(options_.sources);
      std::vector<std::string> scenes;
      for (const auto& entry : catalog->scenes()) scenes.push_back(entry.first);
      fresh->result = {{"robots", catalog->robotNames()},
                       {"objects", catalog->world().objectNames()},
                       {"scenes", scenes},
                       {"skipped", catalog->skipped()}};
    } catch (const std::exception& e) {
      fresh->error =
          RpcError(ErrorCode::kReloadFailed,
                   std::string("reload failed, still serving the old data: ") + e.what());
    }
    post_([this, fresh, catalog, finish] {
      if (catalog) {
        catalog_ = catalog;
        info_ = json();  // describe the new catalog from the next call on
      }
      reloading_ = false;
      finish(std::move(*fresh));
    });
  });
}

}  // namespace hfts::service
