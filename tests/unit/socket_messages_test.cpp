// The engine socket's JSON messages: what a client's message becomes (the DDS interface's own EngineCommand and
// ControlRequest, checked by the gate afterwards), that nothing of a malformed message applies, that Haply's
// shapes are taken, and the state and reply the server writes.
#include "doors/socket/socket_messages.hpp"

#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "hapticd/dds/conversion.hpp"
#include "hapticd/json_reader.hpp"

namespace hapticd::server::socket_messages {
namespace {

struct Parsed {
  Parser parser;
  ClientMessage message;
  std::uint64_t serial = 0;
  std::string text;  // the message parsed last: a scene edit's name and text point into it
  bool parse(std::string message_text, std::string_view engine = "engine") {
    text = std::move(message_text);
    return parser.parse(text, engine, serial, message);
  }
};

TEST(SocketMessages, HaplysSetCursorForceIsAWrenchCommandNumberedByTheServer) {
  Parsed p;
  ASSERT_TRUE(p.parse(
      R"({"inverse3":[{"device_id":"left","commands":{"set_cursor_force":{"vector":{"x":1.5,"y":-2,"z":0.25}}}}],
                          "state_serial": 41})"));
  ASSERT_EQ(p.message.commands.size(), 1u);
  const hapticd_msg_EngineCommand& c = p.message.commands[0];
  EXPECT_EQ(dds::text_of(c.device), "left");
  EXPECT_EQ(dds::text_of(c.engine), "engine");
  EXPECT_EQ(c.kind, hapticd_msg_COMMAND_WRENCH);
  EXPECT_EQ(c.wrench[0], 1.5);
  EXPECT_EQ(c.wrench[1], -2.0);
  EXPECT_EQ(c.wrench[2], 0.25);
  EXPECT_EQ(c.wrench[3], 0.0);
  EXPECT_FALSE(c.local_model);
  EXPECT_EQ(c.state_serial, 41u);
  EXPECT_EQ(c.serial, 1u);
  ASSERT_TRUE(p.parse(
      R"({"devices":[{"device_id":"left","state_serial":42,"commands":{"set_cursor_force":{"vector":{"x":0}}}}]})"));
  EXPECT_EQ(p.message.commands[0].serial, 2u);
  EXPECT_EQ(p.message.commands[0].state_serial, 42u);
}

TEST(SocketMessages, CouplingMotionAndALocalModel) {
  Parsed p;
  ASSERT_TRUE(p.parse(R"({"devices":[
      {"device_id":"a","commands":{"set_coupling":{"position":{"x":0.1,"y":0.2,"z":0.3},"velocity":{"x":1}}}},
      {"device_id":"b","commands":{"set_motion":{"orientation":{"w":0,"x":1,"y":0,"z":0}}}},
      {"device_id":"c","commands":{"set_wrench":{"force":{"z":1},"stiffness":[100,100,100,1,1,1],
                                                 "anchor":{"position":{"x":0.5}}}}}]})"));
  ASSERT_EQ(p.message.commands.size(), 3u);
  const auto& a = p.message.commands[0];
  EXPECT_EQ(a.kind, hapticd_msg_COMMAND_COUPLING);
  EXPECT_EQ(a.command_pose.position[2], 0.3);
  EXPECT_EQ(a.command_pose.orientation[0], 1.0);  // left out: the identity
  EXPECT_EQ(a.twist[0], 1.0);
  const auto& b = p.message.commands[1];
  EXPECT_EQ(b.kind, hapticd_msg_COMMAND_MOTION);
  EXPECT_EQ(b.command_pose.orientation[0], 0.0);
  EXPECT_EQ(b.command_pose.orientation[1], 1.0);
  const auto& c = p.message.commands[2];
  EXPECT_TRUE(c.local_model);
  EXPECT_EQ(c.stiffness[0], 100.0);
  EXPECT_EQ(c.damping[0], 0.0);
  EXPECT_EQ(c.anchor.position[0], 0.5);
  EXPECT_EQ(c.anchor.orientation[0], 1.0);
  EXPECT_EQ(c.wrench[2], 1.0);
}

TEST(SocketMessages, NothingOfAMalformedMessageApplies) {
  Parsed p;
  const std::string bad[] = {
      "not json",
      "[1,2]",
      R"({"devices":[{"device_id":"a","commands":{"set_cursor_force":{"vector":{"x":1}}}},
                     {"device_id":"b","commands":{"set_cursor_force":{"vector":{"x":"far"}}}}]})",
      R"({"devices":[{"device_id":"a","commands":{"set_cursor_force":{}}}]})",
      R"({"devices":[{"device_id":"a","commands":{"explode":{}}}]})",
      R"({"devices":[{"device_id":"a","commands":{"set_coupling":{},"set_motion":{}}}]})",
      R"({"devices":[{"commands":{"set_coupling":{}}}]})",
      R"({"devices":[{"device_id":"a-name-far-longer-than-thirty-one-characters","commands":{"set_coupling":{}}}]})",
      R"({"devices":{"device_id":"a"}})",
      R"({"request":{"id":1,"kind":"self_destruct","device":"a"}})",
      R"({"request":{"id":-1,"kind":"claim","device":"a"}})",
      R"({"request":{"id":1,"kind":"set_parameter","device":"a","values":[1,"x"]}})",
      R"({"request":{"id":1,"kind":"set_parameter","device":"a","values":[1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17]}})",
      R"({"subscribe":"a"})",
      R"({"session":{"configure":{"profile":{"name":""}}}})",
      R"({"state_serial":"x"})",
  };
  for (const std::string& text : bad) {
    EXPECT_FALSE(p.parse(text)) << text;
    EXPECT_FALSE(p.message.error.empty()) << text;
    EXPECT_TRUE(p.message.commands.empty()) << text;
    EXPECT_EQ(p.serial, 0u) << text;  // no command numbers used up
  }
  // Nine commands: at most eight per message.
  std::string nine = R"({"devices":[)";
  for (int i = 0; i < 9; ++i)
    nine += std::string(i ? "," : "") + R"({"device_id":"d","commands":{"set_cursor_force":{"vector":{"x":1}}}})";
  EXPECT_FALSE(p.parse(nine + "]}"));
  EXPECT_EQ(p.serial, 0u);
}

TEST(SocketMessages, ARequestSubscriptionAndProfile) {
  Parsed p;
  ASSERT_TRUE(p.parse(R"({"session":{"configure":{"profile":{"name":"unity-1"}}},"subscribe":["left","right"],
                          "request":{"id":7,"kind":"set_parameter","device":"left","name":"controller.kp","values":[1,2]}})",
                      "socket-3"));
  ASSERT_TRUE(p.message.profile.has_value());
  EXPECT_EQ(*p.message.profile, "unity-1");
  ASSERT_TRUE(p.message.subscribe.has_value());
  EXPECT_EQ(p.message.subscribe->size(), 2u);
  ASSERT_TRUE(p.message.request.has_value());
  const hapticd_msg_ControlRequest& r = *p.message.request;
  EXPECT_EQ(r.kind, hapticd_msg_REQUEST_SET_PARAMETER);
  EXPECT_EQ(dds::text_of(r.client), "unity-1");  // the profile of the same message names the requester
  EXPECT_EQ(dds::text_of(r.device), "left");
  EXPECT_EQ(dds::text_of(r.subject), "controller.kp");
  EXPECT_EQ(r.value_count, 2);
  EXPECT_EQ(r.values[1], 2.0);
  EXPECT_EQ(r.request_id, 7u);
}

// A scene edit hands its object on as the JSON source the client wrote (the scene parses it); a material by name
// becomes a quoted scalar; a move carries its pose; the answer lists the objects.
TEST(SocketMessages, ASceneEditCarriesItsObjectsSourceAndItsAnswerListsTheObjects) {
  Parsed p;
  const std::string object = R"({"name":"ball","shape":"sphere","radius":0.01,"position":[0,1,2],"x":{"a":[[]]}})";
  ASSERT_TRUE(p.parse(R"({"scene":{"id":3,"op":"add","object":)" + object + "}}")) << p.message.error;
  ASSERT_TRUE(p.message.scene.has_value());
  EXPECT_EQ(p.message.scene->id, 3);
  EXPECT_EQ(p.message.scene->edit.op, SceneGate::Op::add);
  EXPECT_EQ(p.message.scene->edit.text, object);
  ASSERT_TRUE(p.parse(R"({"scene":{"id":4,"op":"material","name":"ball","material":"wood"}})"));
  EXPECT_EQ(p.message.scene->edit.text, "\"wood\"");
  EXPECT_EQ(p.message.scene->edit.name, "ball");
  ASSERT_TRUE(p.parse(R"({"scene":{"id":5,"op":"move","name":"ball","position":{"x":1,"y":2,"z":3}}})"));
  EXPECT_EQ(p.message.scene->edit.pose.position.z(), 3.0);
  EXPECT_EQ(p.message.scene->edit.pose.orientation.w(), 1.0);
  EXPECT_FALSE(p.parse(R"({"scene":{"id":6,"op":"add","object":"ball"}})"));
  EXPECT_FALSE(p.message.scene.has_value());
  SceneGate::Reply reply{true, "2 objects"};
  reply.objects.emplace();
  reply.objects->push_back({"ball", "sphere", 7, true, 0, {}});
  reply.objects->push_back({"rock \"one\"", "mesh", 8, false, 5120, {}});
  const std::string text = scene_reply(9, reply);
  JsonReader json;
  ASSERT_TRUE(json.parse(text)) << text;
  const JsonReader::Value r = json.root()["scene_reply"];
  EXPECT_EQ(r["id"].number_or(0), 9);
  EXPECT_EQ(r["objects"].size(), 2u);
  EXPECT_EQ(*r["objects"].at(1)["shape"].string(), "mesh");
  EXPECT_EQ(r["objects"].at(1)["triangles"].number_or(0), 5120);
  EXPECT_EQ(*r["objects"].at(0)["moving"].boolean(), true);
  // An empty scene and a hand touching nothing answer empty lists (a client reads the key whatever the count); an
  // edit's answer has neither.
  SceneGate::Reply none{true, "0 contacts"};
  none.contacts.emplace();
  const std::string no_contacts = scene_reply(10, none);  // the reader's values point into the text
  ASSERT_TRUE(json.parse(no_contacts));
  EXPECT_EQ(json.root()["scene_reply"]["contacts"].kind(), JsonReader::Kind::array);
  EXPECT_EQ(json.root()["scene_reply"]["contacts"].size(), 0u);
  none.contacts.reset();
  none.objects.emplace();
  const std::string no_objects = scene_reply(11, none);
  ASSERT_TRUE(json.parse(no_objects));
  EXPECT_EQ(json.root()["scene_reply"]["objects"].kind(), JsonReader::Kind::array);
  const std::string added = scene_reply(12, SceneGate::Reply{true, "added"});
  ASSERT_TRUE(json.parse(added));
  EXPECT_FALSE(json.root()["scene_reply"]["objects"]);
  EXPECT_FALSE(json.root()["scene_reply"]["contacts"]);
}

TEST(SocketMessages, AMeshUploadsPartCarriesItsNumbersAndAnAddNamesItsUpload) {
  Parsed p;
  ASSERT_TRUE(p.parse(R"({"scene":{"id":1,"op":"upload","upload":"rock","part":2,"parts":5,)"
                      R"("vertices":[0,0.5,-1e-3,1,2,3],"triangles":[0,1,4294967295]}})"))
      << p.message.error;
  const SceneGate::Edit& e = p.message.scene->edit;
  EXPECT_EQ(e.op, SceneGate::Op::upload);
  EXPECT_EQ(e.upload, "rock");
  EXPECT_EQ(e.part, 2);
  EXPECT_EQ(e.parts, 5);
  EXPECT_EQ(std::vector<double>(e.vertices.begin(), e.vertices.end()), (std::vector<double>{0, 0.5, -1e-3, 1, 2, 3}));
  EXPECT_EQ(std::vector<std::uint32_t>(e.triangles.begin(), e.triangles.end()),
            (std::vector<std::uint32_t>{0, 1, 4294967295u}));
  ASSERT_TRUE(p.parse(R"({"scene":{"id":2,"op":"add","object":{"name":"rock","shape":"mesh","upload":"rock"}}})"));
  EXPECT_EQ(p.message.scene->edit.upload, "rock");
  // Malformed: each refused whole, with what an upload needs.
  for (const char* bad : {
           R"({"scene":{"id":3,"op":"upload","upload":"r","part":0,"parts":1,"vertices":[0],"triangles":[1.5]}})",
           R"({"scene":{"id":3,"op":"upload","upload":"r","part":0,"parts":1,"vertices":[0],"triangles":[-1]}})",
           R"({"scene":{"id":3,"op":"upload","upload":"r","part":0,"parts":1,"vertices":["0"],"triangles":[]}})",
           R"({"scene":{"id":3,"op":"upload","upload":"r","part":1,"parts":1,"vertices":[],"triangles":[]}})",
           R"({"scene":{"id":3,"op":"upload","upload":"r","part":0.5,"parts":2,"vertices":[],"triangles":[]}})",
           R"({"scene":{"id":3,"op":"upload","part":0,"parts":1,"vertices":[],"triangles":[]}})",
           R"({"scene":{"id":3,"op":"upload","upload":"r","part":0,"parts":1,"vertices":{},"triangles":[]}})",
           R"({"scene":{"id":3,"op":"add","object":{"name":"r","shape":"mesh","upload":7}}})",
       }) {
    EXPECT_FALSE(p.parse(bad)) << bad;
    EXPECT_FALSE(p.message.scene.has_value()) << bad;
    EXPECT_FALSE(p.message.error.empty()) << bad;
  }
}

TEST(SocketMessages, TheStateAndTheReplyAreJsonAClientReads) {
  hapticd_msg_DeviceState s{};
  dds::set_text(s.device, "left");
  dds::set_text(s.owner, "unity \"1\"");
  s.serial = 12;
  s.handle_pose.position[0] = 0.25;
  s.handle_pose.orientation[0] = 1.0;
  s.twist[4] = -2.0;
  s.mode = hapticd_msg_MODE_SAFE;
  s.buttons = 5;
  std::string text;
  state(s, text);
  JsonReader json;
  ASSERT_TRUE(json.parse(text)) << json.error() << "\n" << text;
  const auto device = json.root()["devices"].at(0);
  EXPECT_EQ(device["device_id"].string(), "left");
  EXPECT_EQ(device["state"]["serial"].number(), 12.0);
  EXPECT_EQ(device["state"]["cursor_position"]["x"].number(), 0.25);
  EXPECT_EQ(device["state"]["angular_velocity"]["y"].number(), -2.0);
  EXPECT_EQ(device["state"]["buttons"].number(), 5.0);
  EXPECT_EQ(device["status"]["mode"].string(), "safe");
  EXPECT_TRUE(device["status"]["owner"]);

  hapticd_msg_ControlReply r{};
  dds::set_text(r.device, "left");
  dds::set_text(r.message, "claimed by 'x'");
  r.value_count = 2;
  r.values[0] = 1.5;
  r.values[1] = std::nan("");
  const std::string reply_text = reply(9, r);
  ASSERT_TRUE(json.parse(reply_text)) << reply_text;
  EXPECT_EQ(json.root()["reply"]["id"].number(), 9.0);
  EXPECT_EQ(json.root()["reply"]["accepted"].boolean(), false);
  EXPECT_EQ(json.root()["reply"]["values"].size(), 2u);
  EXPECT_EQ(json.root()["reply"]["values"].at(1).kind(), JsonReader::Kind::null);  // NaN: null

  // An event: every kind by its name, one past the last as "other".
  hapticd_msg_Event e{};
  dds::set_text(e.device, "left");
  e.serial = 4;
  e.kind = hapticd_msg_EVENT_PARAMETER;
  dds::set_text(e.code, "virtual_model");
  dds::set_text(e.message, "virtual_model.coupling_stiffness_n_per_m = 2500 (set by 'console')");
  const std::string event_text = event(e);
  ASSERT_TRUE(json.parse(event_text)) << event_text;
  EXPECT_EQ(json.root()["event"]["device"].string(), "left");
  EXPECT_EQ(json.root()["event"]["serial"].number(), 4.0);
  EXPECT_EQ(json.root()["event"]["kind"].string(), "parameter");
  EXPECT_EQ(json.root()["event"]["code"].string(), "virtual_model");
  EXPECT_EQ(event_kind_name(hapticd_msg_EVENT_OWNER), "owner");
  EXPECT_EQ(event_kind_name(hapticd_msg_EVENT_PARAMETER + 1), "other");
}

}  // namespace
}  // namespace hapticd::server::socket_messages

namespace hapticd::server::socket_messages {
namespace {

// Hardening round 4, item 4: bytes that are not UTF-8 in a peer's text (an owner's id, a refusal quoting it) are
// written as U+FFFD, so the text stays valid for every JSON client (Python's websockets closed with 1007 before);
// valid multi-byte text passes unchanged.
TEST(SocketMessages, TextThatIsNotUtf8IsWrittenAsReplacementCharacters) {
  hapticd_msg_DeviceState s{};
  dds::set_text(s.device, "left");
  dds::set_text(s.owner, "intruder\xff\xfe\xc0\x80 \xed\xa0\x80 \xf4\x90\x80\x80 caf\xc3\xa9 \xe2\x82");
  s.handle_pose.orientation[0] = 1.0;
  std::string text;
  state(s, text);
  EXPECT_TRUE(valid_utf8(text)) << text;
  EXPECT_NE(text.find("intruder\\ufffd\\ufffd\\ufffd\\ufffd \\ufffd"), std::string::npos) << text;
  EXPECT_NE(text.find("caf\xc3\xa9 \\ufffd\\ufffd"), std::string::npos) << text;
  JsonReader json;
  ASSERT_TRUE(json.parse(text)) << json.error();
  hapticd_msg_ControlReply r{};
  dds::set_text(r.device, "left");
  dds::set_text(r.message, "stopped by '\xff'");
  EXPECT_TRUE(valid_utf8(reply(1, r)));
}

TEST(SocketMessages, Utf8IsCheckedAsRfc3629SaysIt) {
  EXPECT_TRUE(valid_utf8(""));
  EXPECT_TRUE(valid_utf8("plain"));
  EXPECT_TRUE(valid_utf8("\xc3\xa9\xe2\x82\xac\xf0\x9f\x98\x80\xf4\x8f\xbf\xbf"));  // e-acute, euro, emoji, U+10FFFF
  EXPECT_FALSE(valid_utf8("\xc0\xaf"));                                             // overlong '/'
  EXPECT_FALSE(valid_utf8("\xe0\x80\xaf"));                                         // overlong
  EXPECT_FALSE(valid_utf8("\xed\xa0\x80"));                                         // a surrogate
  EXPECT_FALSE(valid_utf8("\xf4\x90\x80\x80"));                                     // above U+10FFFF
  EXPECT_FALSE(valid_utf8("\xe2\x82"));                                             // cut short
  EXPECT_FALSE(valid_utf8("\x80"));                                                 // a lone continuation
  char name[8] = {'o', 'k', '\xff', '\0'};
  EXPECT_FALSE(dds::valid_text(name));
  name[2] = '\0';
  EXPECT_TRUE(dds::valid_text(name));
}

}  // namespace
}  // namespace hapticd::server::socket_messages
